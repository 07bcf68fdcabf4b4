#pragma once
// What host and plugin agree on: the ABI handshake (PluginDescriptor) and the Registrar a plugin
// registers its factories with. Plugin authors use the macros of plugin.hpp instead.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "salsa/behavior.hpp"
#include "salsa/contact.hpp"
#include "salsa/map.hpp"
#include "salsa/metric.hpp"
#include "salsa/target.hpp"
#include "salsa/wind.hpp"

namespace salsa {

/// Bumped whenever a type a plugin sees changes layout or meaning.
inline constexpr std::uint32_t abi_version = 11;  // 2: metrics, Behavior::senses; 3: Behavior::inspect; 4: Param members, plugin authors' kit; 5: groups, drone status, battery, Behavior::resize; 6: wind fields, Perception::air_velocity, messages (Perception::messages, broadcast, Behavior::message_size), TargetSeen::phantom; 7: Message::offset, range() and bearing() computed when asked; 8: ContactHandler::sightings; 9: Perception::wind; 10: Behavior::shared_state; 11: moving targets (TargetKind::moves, max_speed, move; TargetState::found_position) (docs/plugins.md#abi-policy)

/// Types cross the library boundary (std::string, std::function, vectors), so plugin and host must
/// agree on the C++ library ABI as well; this tag folds the relevant facts into one number. The loader
/// decodes a mismatch back into words, so keep this layout (or teach the loader a new one).
constexpr std::uint32_t toolchain_tag() {
  return static_cast<std::uint32_t>(sizeof(std::string) << 16 | sizeof(std::function<void()>) << 8 |
                                    sizeof(std::vector<int>) << 1 |
#if defined(_GLIBCXX_USE_CXX11_ABI)
                                    _GLIBCXX_USE_CXX11_ABI
#else
                                    0
#endif
  );
}

enum class PluginKind : std::uint8_t { behavior, target, map, contact_handler, metric, wind };

inline const char* to_string(PluginKind k) {
  switch (k) {
    case PluginKind::behavior: return "behavior";
    case PluginKind::target: return "target";
    case PluginKind::map: return "map";
    case PluginKind::contact_handler: return "contact handler";
    case PluginKind::metric: return "metric";
    case PluginKind::wind: return "wind";
  }
  return "?";
}

template <class Base>
struct Factory {
  std::string name;
  std::string brief;
  Parameters parameters;
  std::function<std::unique_ptr<Base>()> create;
};

class Registrar {
 public:
  virtual ~Registrar() = default;
  virtual void add(Factory<Behavior> f) = 0;
  virtual void add(Factory<TargetKind> f) = 0;
  virtual void add(Factory<MapGenerator> f) = 0;
  virtual void add(Factory<ContactHandler> f) = 0;
  virtual void add(Factory<Metric> f) = 0;
  virtual void add(Factory<WindField> f) = 0;
};

/// The handshake. The first four fields keep their place in every ABI version, so any loader can read
/// them from any plugin.
struct PluginDescriptor {
  std::uint32_t abi_version;
  std::uint32_t descriptor_size;
  std::uint32_t descriptor_align;
  std::uint32_t toolchain;
  const char* name;
  const char* version;
  const char* author;
  const char* brief;
  void (*register_all)(Registrar&);
};

inline constexpr const char* entry_symbol = "salsa_plugin_descriptor";

}  // namespace salsa
