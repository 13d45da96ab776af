// prompts.json as `segment --prompts` reads it.
#include "dataset/prompts.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = pg::fuzz::write_input(data, size, "prompts.json");
    pg::fuzz::expect_clean(path, [&] { pg::data::read_prompts(path); });
    return 0;
}
