// tests/test_main.cpp — the doctest runner. Every suite links into this one binary; ctest runs it per suite.
#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include "fp_env.h"

#include <cstdio>

int main(int argc, char** argv) {
    // The simulation's results are only meaningful under IEEE defaults; say so up front if the runner is not.
    const std::string env = unison::checkFloatingPointEnvironment();
    if (!env.empty()) std::fprintf(stderr, "warning: %s\n", env.c_str());
    doctest::Context context(argc, argv);
    return context.run();
}
