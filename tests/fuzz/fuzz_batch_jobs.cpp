// batch's JOBS.json: read and checked whole before any job runs, each job's options through
// segment's own parser.
#include "app/cli/batch_jobs.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = pg::fuzz::write_input(data, size, "jobs.json");
    pg::fuzz::expect_clean(path, [&] { pg::app::read_jobs(path); });
    return 0;
}
