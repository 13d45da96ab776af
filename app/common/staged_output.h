#pragma once
// A command's outputs appear together or not at all: they are written under a hidden staging
// folder inside OUT and moved into OUT, file by file (each a rename), only when the command
// succeeds. A failure (an exception: a bad input, the device out of memory, a full disk)
// removes the staging folder, so OUT holds what it held before; one left by a killed process
// is removed by the next run into the same OUT.
#include <filesystem>

namespace pg::app {

class StagedOutput {
public:
    // Creates OUT and the staging folder; InputError if OUT is a file or cannot be written.
    explicit StagedOutput(const std::filesystem::path& out);
    ~StagedOutput();
    StagedOutput(const StagedOutput&) = delete;
    StagedOutput& operator=(const StagedOutput&) = delete;

    // Where to write; its sub-folders land as OUT's sub-folders.
    const std::filesystem::path& dir() const { return staging_; }
    // Moves every file into OUT (replacing files of the same name) and removes the staging folder.
    void commit();

private:
    std::filesystem::path out_, staging_;
    bool committed_ = false;
};

}  // namespace pg::app
