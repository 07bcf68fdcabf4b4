// A shared library that needs a function nobody defines: dlopen (RTLD_NOW) refuses it, and the
// message must name the original file, not the private copy that was loaded.
extern "C" int salsa_test_missing_function();
extern "C" __attribute__((visibility("default"))) int salsa_test_calls_missing() { return salsa_test_missing_function(); }
