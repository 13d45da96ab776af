// Scene readers: chosen by content as `load_scene` does, under the extension PG_FUZZ_EXT
// (.ply: INRIA, 2DGS, PlayCanvas compressed; .splat; .spz; .sog: a bundled SOG, zip + WebP).
#include "dataset/formats/scene_io.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = pg::fuzz::write_input(data, size, std::string("scene") + PG_FUZZ_EXT);
    pg::fuzz::expect_clean(path, [&] { pg::data::load_scene(path); });
    return 0;
}
