// A plain shared library that is not a salsa plugin: no salsa_plugin_descriptor.
extern "C" __attribute__((visibility("default"))) int salsa_test_noentry_answer() { return 42; }
