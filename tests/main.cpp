// The single doctest main. Suites: "unit" (pieces), "physics" (verification against analytic
// solutions and conservation laws), "cli" (the mrjam executable end to end).
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>
