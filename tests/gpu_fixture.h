#pragma once
// The Vulkan context shared by the tests of one process: validation (with synchronization
// validation) always on, and any validation message fails the run.
#include <cstdlib>

#include "engine/vk/context.h"
#include "tests/exit_checks.h"

namespace pg::test {

inline vk::Context& gpu() {
    static vk::Context* ctx = [] {
        vk::ContextOptions o;
        o.validation = true;
        o.quiet = true;
        exit_checks().push_back({"no Vulkan validation messages", [] { return vk::Context::validation_message_count() == 0; }});
        return new vk::Context(o);  // leaked on purpose: destroyed after Catch's statics otherwise
    }();
    return *ctx;
}

}  // namespace pg::test
