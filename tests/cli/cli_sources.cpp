// The CLI's option parser, compiled into the test binary (which links only the library).
// Remove this file if tests/CMakeLists.txt ever adds src/cli/options.cpp to fdmsurf_tests.
#include "cli/options.cpp"
