// Camera files: INRIA cameras.json or nerfstudio transforms.json (PG_FUZZ_NAME), read by
// `load_cameras` as --cameras is.
#include "dataset/formats/camera_io.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = pg::fuzz::write_input(data, size, PG_FUZZ_NAME);
    pg::fuzz::expect_clean(path, [&] { pg::data::load_cameras(path); });
    return 0;
}
