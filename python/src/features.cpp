// What salsa.Env's observation features (python/salsa/_features.py) do faster in C++ than numpy can:
// each drone's k nearest items of a compressed-sparse-rows list, a partial sort per row rather than one
// sort of every item.
#include <pybind11/numpy.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "bindings.hpp"

namespace salsa::python {

namespace {

/// (n, k) item indices, row r's nearest first, -1 past its items. Ties keep item order.
py::array_t<std::intptr_t> nearest(const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>& offsets,
                                   const py::array_t<double, py::array::c_style | py::array::forcecast>& distance, int k) {
  if (offsets.ndim() != 1 || offsets.shape(0) < 1 || distance.ndim() != 1)
    throw py::value_error("_nearest: offsets (n + 1,) and distance (m,) (allowed: one-dimensional arrays)");
  if (k < 0) throw py::value_error("_nearest: k " + std::to_string(k) + " is negative (allowed: >= 0)");
  const auto n = offsets.shape(0) - 1;
  const std::int64_t* off = offsets.data();
  const double* d = distance.data();
  const auto m = distance.shape(0);
  if (off[0] != 0 || off[n] != m)
    throw py::value_error("_nearest: offsets run from 0 to " + std::to_string(off[n]) + " (allowed: 0 to the " +
                          std::to_string(m) + " items)");
  py::array_t<std::intptr_t> out({n, static_cast<py::ssize_t>(k)});
  std::intptr_t* o = out.mutable_data();
  std::fill(o, o + n * k, -1);
  {
    py::gil_scoped_release nogil;
    std::vector<std::intptr_t> row;
    for (py::ssize_t r = 0; r < n; ++r) {
      const std::int64_t begin = off[r], end = off[r + 1];
      if (end < begin || end > m) continue;  // not compressed rows: checked above at the ends
      row.resize(static_cast<std::size_t>(end - begin));
      for (std::int64_t i = begin; i < end; ++i) row[static_cast<std::size_t>(i - begin)] = i;
      const auto keep = std::min<std::size_t>(row.size(), static_cast<std::size_t>(k));
      auto closer = [d](std::intptr_t a, std::intptr_t b) { return d[a] < d[b] || (d[a] == d[b] && a < b); };
      std::partial_sort(row.begin(), row.begin() + static_cast<std::ptrdiff_t>(keep), row.end(), closer);
      std::copy_n(row.begin(), keep, o + r * k);
    }
  }
  return out;
}

}  // namespace

void bind_features(py::module_& m) {
  m.def("_nearest", &nearest, py::arg("offsets"), py::arg("distance"), py::arg("k"),
        "Each row's k nearest items of compressed rows (offsets (n + 1,), distance (m,)): (n, k) indices, "
        "nearest first, -1 where a row has fewer (salsa.Env's neighbours and targets features).");
}

}  // namespace salsa::python
