#pragma once
// Shared by the libFuzzer harnesses (docs/reliability.md): the fuzzed bytes as a temporary
// file for readers that only take a path, and a stop that makes a broken invariant a finding.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace ggg_fuzz {

// The bytes written to a fresh file in the temporary folder whose name ends in `suffix`
// (the readers pick the format by it); removed again on destruction.
class TempFile {
public:
    TempFile(const std::uint8_t* data, std::size_t size, std::string_view suffix);
    ~TempFile();
    TempFile(const TempFile&) = delete;
    TempFile& operator=(const TempFile&) = delete;
    const std::string& path() const { return path_; }

private:
    std::string path_;
};

// Prints `what` and aborts: libFuzzer saves the input as a crash.
[[noreturn]] void fail(const std::string& what);

} // namespace ggg_fuzz
