// A COLMAP model folder, binary or text (PG_FUZZ_EXT): cameras and images from one input.
#include "dataset/formats/camera_io.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto dir = pg::fuzz::scratch() / "model";
    std::filesystem::create_directories(dir);
    pg::fuzz::split_input(data, size, dir / (std::string("cameras") + PG_FUZZ_EXT), dir / (std::string("images") + PG_FUZZ_EXT));
    pg::fuzz::expect_clean(dir / "cameras", [&] { pg::data::load_cameras(dir); });
    return 0;
}
