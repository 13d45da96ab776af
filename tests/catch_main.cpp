// Catch2 runner that also fails the process when an exit check fails (e.g. a Vulkan
// validation message was printed during the run).
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include <cstdio>

#include "tests/exit_checks.h"

int main(int argc, char** argv) {
    int result = Catch::Session().run(argc, argv);
    for (auto& [name, check] : pg::test::exit_checks())
        if (!check()) {
            std::fprintf(stderr, "FAILED exit check: %s\n", name.c_str());
            if (result == 0) result = 1;
        }
    return result;
}
