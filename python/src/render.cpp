// Session.render: the simulation drawn as the desktop draws it (salsa_frame, gui-qt/frame/), into a numpy
// RGB array, on the offscreen platform when the process has no QGuiApplication (offscreen.hpp).
#include <pybind11/numpy.h>

#include <QImage>
#include <cstring>

#include "bindings.hpp"
#include "frame_renderer.hpp"
#include "offscreen.hpp"

namespace salsa::python {

py::array render_session(const Session& session, int width, int height) {
  constexpr int most = 16384;
  for (auto [name, v] : {std::pair{"width", width}, std::pair{"height", height}})
    if (v < 1 || v > most)
      throw py::value_error(std::string(name) + ": " + std::to_string(v) + " is out of range (allowed: whole number of pixels in [1, " +
                            std::to_string(most) + "])");
  if (!gui::ensure_gui_application())
    throw py::value_error("render: this process has a QCoreApplication without a GUI, which cannot draw text (allowed: "
                          "none, or a QGuiApplication or QApplication)");
  const Simulation& sim = session.simulation();
  gui::Snapshot snap;
  snap.scene = gui::scene_of(sim);
  gui::fill_snapshot(snap, sim, session.current().has_wind());
  snap.found = gui::found_flags(sim);
  snap.targets_found = sim.targets_found();
  snap.test_name = session.test().name;
  const QImage frame = gui::render_frame(snap, gui::ViewOptions{}, QSize(width, height)).convertToFormat(QImage::Format_RGB888);
  py::array_t<std::uint8_t> out({py::ssize_t{height}, py::ssize_t{width}, py::ssize_t{3}});
  auto* to = out.mutable_data();
  const auto row = static_cast<std::size_t>(width) * 3;
  for (int y = 0; y < height; ++y) std::memcpy(to + static_cast<std::size_t>(y) * row, frame.constScanLine(y), row);
  return out;
}

}  // namespace salsa::python
