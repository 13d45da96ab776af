#pragma once
// One error type for bad input: it names the file (or argument) and the reason, and is
// caught once, at the edge (the CLI prints it and exits non-zero).
#include <stdexcept>
#include <string>

namespace pg::data {

class InputError : public std::runtime_error {
public:
    InputError(std::string where, std::string reason)
        : std::runtime_error(where + ": " + reason), where_(std::move(where)), reason_(std::move(reason)) {}
    const std::string& where() const { return where_; }
    const std::string& reason() const { return reason_; }

private:
    std::string where_, reason_;
};

}  // namespace pg::data
