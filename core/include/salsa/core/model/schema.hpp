#pragma once
// A model's settings, declared once: each number's declaration (name, default, range, unit, meaning)
// and where it lives in the model's struct. The test reader and writer, timed changes, sweeps, tune
// keys, `salsa describe` and the desktop's panels iterate a model's schema, so a setting added to it
// reaches all of them. One shape for every model: the drone, the comm model, the wind.
#include <initializer_list>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "salsa/parameters.hpp"

namespace salsa {

/// One setting of a model's struct `S`. `Section` names the parts of a model that can be in use or not
/// (DroneSection for a drone); a model of one part leaves it at 0.
template <class S, class Section = int>
struct Field {
  Parameter spec;  ///< name ("gusts.strength": a dot for nesting), default, range, unit, meaning; step 1: a whole number
  double (*read)(const S&) = nullptr;
  void (*write)(S&, double) = nullptr;
  bool flag = false;         ///< true/false in files (0 or 1 in timed changes and sweeps)
  /// Part of the world key that pairs seeds (queue.hpp): the settings that shape the world a test starts
  /// in. Those that do not (a battery, sensor noise) let tests that differ only in them share a world.
  bool shapes_world = true;
  Section section{};
  double get(const S& s) const { return read(s); }
  void set(S& s, double v) const { write(s, v); }
};

template <class>
struct member_of;
template <class S, class T>
struct member_of<T S::*> {
  using owner = S;
  using type = T;
};

/// The field of member `M` (`&S::name`): a number (double), a whole number (int) or a flag (bool).
template <auto M, class Section = int>
Field<typename member_of<decltype(M)>::owner, Section> field(Parameter spec, Section section = {}, bool shapes_world = true) {
  using S = typename member_of<decltype(M)>::owner;
  using T = typename member_of<decltype(M)>::type;
  return {std::move(spec), [](const S& s) { return static_cast<double>(s.*M); },
          [](S& s, double v) {
            if constexpr (std::is_same_v<T, bool>) s.*M = v != 0;
            else s.*M = static_cast<T>(v);
          },
          std::is_same_v<T, bool>, shapes_world, section};
}

/// A model's fields in file order, with the look-ups every user needs.
template <class S, class Section = int>
class Schema {
 public:
  using Entry = Field<S, Section>;
  Schema(std::initializer_list<Entry> fields) : fields_(fields) {}
  auto begin() const { return fields_.begin(); }
  auto end() const { return fields_.end(); }
  std::size_t size() const { return fields_.size(); }
  const Entry& operator[](std::size_t i) const { return fields_[i]; }
  /// The field called `name`, or nullptr.
  const Entry* find(std::string_view name) const {
    for (const Entry& f : fields_)
      if (f.spec.name == name) return &f;
    return nullptr;
  }
  /// "range, line_of_sight, ...": the names, for messages.
  std::string names() const {
    std::string out;
    for (const Entry& f : fields_) out += (out.empty() ? "" : ", ") + f.spec.name;
    return out;
  }

 private:
  std::vector<Entry> fields_;
};

}  // namespace salsa
