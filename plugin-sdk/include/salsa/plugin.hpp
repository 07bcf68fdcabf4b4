#pragma once
// Plugin registration. A plugin library registers any number of behaviors, target kinds, maps, contact
// handlers, metrics and wind fields with one macro each; the library exports one C symbol, `salsa_plugin_descriptor`,
// that the loader reads and checks before it calls anything else.
#include <type_traits>

#include "salsa/registry.hpp"

namespace salsa {
namespace detail {

// Hidden so that each plugin library keeps its own list (a default-visibility inline static would be
// merged across libraries by the dynamic linker).
__attribute__((visibility("hidden"))) inline std::vector<void (*)(Registrar&)>& registrations() {
  static std::vector<void (*)(Registrar&)> list;
  return list;
}

/// `T::declare()` if it has one, then the Param members of a probe instance (constructed once, at
/// registration).
template <class T>
Parameters declared_parameters() {
  Parameters out;
  if constexpr (requires { T::declare(); }) out = T::declare();
  if constexpr (std::is_default_constructible_v<T>) {
    T probe;
    for (auto& p : static_cast<const Configurable&>(probe).bound_parameters()) out.push_back(std::move(p));
  }
  return out;
}

template <class Base, class T>
Factory<Base> make_factory(const char* name, const char* brief) {
  Parameters params = declared_parameters<T>();
  return {name, brief, params, [params] {
            auto object = std::make_unique<T>();
            object->set_parameters(ParameterValues(params));
            return std::unique_ptr<Base>(std::move(object));
          }};
}

__attribute__((visibility("hidden"))) inline void register_all(Registrar& r) {
  for (auto add : registrations()) add(r);
}

}  // namespace detail
}  // namespace salsa

// Plugin metadata; salsa_add_plugin() defines these from its arguments.
#ifndef SALSA_PLUGIN_NAME
#define SALSA_PLUGIN_NAME "unnamed"
#endif
#ifndef SALSA_PLUGIN_VERSION
#define SALSA_PLUGIN_VERSION "0.0.0"
#endif
#ifndef SALSA_PLUGIN_AUTHOR
#define SALSA_PLUGIN_AUTHOR ""
#endif
#ifndef SALSA_PLUGIN_BRIEF
#define SALSA_PLUGIN_BRIEF ""
#endif
#ifndef SALSA_PLUGIN_ABI  // only the test suite overrides this, to build a plugin for another ABI
#define SALSA_PLUGIN_ABI ::salsa::abi_version
#endif

namespace salsa::detail {
__attribute__((visibility("hidden"))) inline const PluginDescriptor descriptor{
    SALSA_PLUGIN_ABI,     sizeof(PluginDescriptor), alignof(PluginDescriptor), toolchain_tag(),
    SALSA_PLUGIN_NAME,    SALSA_PLUGIN_VERSION,     SALSA_PLUGIN_AUTHOR,       SALSA_PLUGIN_BRIEF,
    &register_all};
}

// The one exported entry point; inline so that several files of one plugin may each use the macros,
// `used` because GCC emits an inline function only where a call or address survives, and none does.
extern "C" __attribute__((visibility("default"), used)) inline const ::salsa::PluginDescriptor*
salsa_plugin_descriptor() {
  return &::salsa::detail::descriptor;
}

#define SALSA_DETAIL_CAT2(a, b) a##b
#define SALSA_DETAIL_CAT(a, b) SALSA_DETAIL_CAT2(a, b)
#define SALSA_DETAIL_REGISTER(Base, Class, name, brief)                                                 \
  namespace {                                                                                          \
  [[maybe_unused]] const bool SALSA_DETAIL_CAT(salsa_registered_, __COUNTER__) = [] {                  \
    ::salsa::detail::registrations().push_back(                                                        \
        [](::salsa::Registrar& r) { r.add(::salsa::detail::make_factory<Base, Class>(name, brief)); }); \
    return (void)&salsa_plugin_descriptor, true;                                                       \
  }();                                                                                                 \
  }

/// Register a behavior class (derived from salsa::Behavior; optional `static Parameters declare()`).
#define SALSA_BEHAVIOR(Class, name, brief) SALSA_DETAIL_REGISTER(::salsa::Behavior, Class, name, brief)
/// Register a target kind (derived from salsa::TargetKind).
#define SALSA_TARGET(Class, name, brief) SALSA_DETAIL_REGISTER(::salsa::TargetKind, Class, name, brief)
/// Register a map generator (derived from salsa::MapGenerator).
#define SALSA_MAP(Class, name, brief) SALSA_DETAIL_REGISTER(::salsa::MapGenerator, Class, name, brief)
/// Register a contact handler (derived from salsa::ContactHandler).
#define SALSA_CONTACT_HANDLER(Class, name, brief) \
  SALSA_DETAIL_REGISTER(::salsa::ContactHandler, Class, name, brief)
/// Register a metric (derived from salsa::Metric).
#define SALSA_METRIC(Class, name, brief) SALSA_DETAIL_REGISTER(::salsa::Metric, Class, name, brief)
/// Register a wind field (derived from salsa::WindField).
#define SALSA_WIND(Class, name, brief) SALSA_DETAIL_REGISTER(::salsa::WindField, Class, name, brief)
