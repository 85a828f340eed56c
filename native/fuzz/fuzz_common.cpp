#include "fuzz_common.hpp"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <unistd.h>

namespace ggg_fuzz {

TempFile::TempFile(const std::uint8_t* data, std::size_t size, std::string_view suffix) {
    static unsigned counter = 0;
    path_ = (std::filesystem::temp_directory_path() /
             ("ggg-fuzz-" + std::to_string(::getpid()) + "-" + std::to_string(counter++ % 8) + std::string(suffix)))
                .string();
    std::FILE* f = std::fopen(path_.c_str(), "wb");
    if (!f) fail("cannot write the temporary file " + path_);
    if (size > 0 && std::fwrite(data, 1, size, f) != size) fail("cannot write the temporary file " + path_);
    if (std::fclose(f) != 0) fail("cannot write the temporary file " + path_);
}

TempFile::~TempFile() {
    std::error_code ec;
    std::filesystem::remove(path_, ec);
}

void fail(const std::string& what) {
    std::fprintf(stderr, "ggg fuzz: %s\n", what.c_str());
    std::fflush(stderr);
    std::abort();
}

} // namespace ggg_fuzz

// Sanitizer settings built into every harness, so that running one by hand behaves as
// scripts/fuzz.sh does: any UB report stops the run (a finding), except the suppressed
// known issues of third-party code in ubsan.supp. UBSAN_OPTIONS/ASAN_OPTIONS still override.
extern "C" const char* __ubsan_default_options() {
    return "halt_on_error=1:print_stacktrace=1:report_error_type=1:suppressions=" GGG_FUZZ_UBSAN_SUPPRESSIONS;
}
extern "C" const char* __asan_default_options() {
    return "detect_leaks=1:allocator_may_return_null=0";
}
