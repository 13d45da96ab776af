// The viewer's --script actions file.
#include "app/viewer/script.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = pg::fuzz::write_input(data, size, "script.json");
    pg::fuzz::expect_clean(path, [&] { pg::viewer::read_script(path); });
    return 0;
}
