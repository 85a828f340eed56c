#include "ggg/files.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "ggg/error.hpp"

namespace ggg {
namespace {

namespace fs = std::filesystem;

std::string size_text(std::size_t bytes) {
    if (bytes >= (std::size_t{1} << 30) && bytes % (std::size_t{1} << 30) == 0) return std::to_string(bytes >> 30) + " GiB";
    if (bytes >= (std::size_t{1} << 20) && bytes % (std::size_t{1} << 20) == 0) return std::to_string(bytes >> 20) + " MiB";
    return std::to_string(bytes) + " bytes";
}

std::string errno_text(int error) { return std::strerror(error); }

class FileDescriptor {
public:
    explicit FileDescriptor(int fd) : fd_(fd) {}
    FileDescriptor(const FileDescriptor&) = delete;
    FileDescriptor& operator=(const FileDescriptor&) = delete;
    ~FileDescriptor() { close(); }
    int get() const { return fd_; }
    int close() {
        if (fd_ < 0) return 0;
        const int result = ::close(fd_);
        fd_ = -1;
        return result;
    }

private:
    int fd_;
};

const char* kind_of(fs::file_type type) {
    switch (type) {
    case fs::file_type::directory: return "folder";
    case fs::file_type::symlink: return "symbolic link";
    case fs::file_type::block: return "block device";
    case fs::file_type::character: return "character device";
    case fs::file_type::fifo: return "pipe";
    case fs::file_type::socket: return "socket";
    default: return "special file";
    }
}

// The permissions a new file gets: 0666 less the process's umask, read without changing it
// (umask() both reads and sets, which races with other threads).
mode_t new_file_mode() {
    mode_t mask = 022;
    std::ifstream status("/proc/self/status");
    std::string key;
    while (status >> key) {
        if (key == "Umask:") {
            std::string value;
            status >> value;
            mask = static_cast<mode_t>(std::strtoul(value.c_str(), nullptr, 8));
            break;
        }
    }
    return static_cast<mode_t>(0666 & ~mask);
}

} // namespace

std::string read_text_file(const std::string& path, std::size_t limit) {
    const int fd_value = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY);
    if (fd_value < 0) {
        const int error = errno;
        if (error == ENOENT || error == ENOTDIR) throw InputError(path + ": no such file");
        throw InputError(path + ": cannot open (" + errno_text(error) + ")");
    }
    FileDescriptor fd(fd_value);
    struct stat info {};
    if (::fstat(fd.get(), &info) != 0) throw InputError(path + ": cannot open (" + errno_text(errno) + ")");
    if (S_ISDIR(info.st_mode)) throw InputError(path + ": is a folder, not a file");
    const bool regular = S_ISREG(info.st_mode);
    if (regular && static_cast<std::uint64_t>(info.st_size) > limit) {
        throw InputError(path + ": the file is larger than " + size_text(limit) + ", the most the project reads");
    }
    const std::size_t most = regular ? limit : std::min(limit, max_stream_bytes);
    std::string text;
    if (regular) text.reserve(static_cast<std::size_t>(info.st_size));
    char chunk[1 << 16];
    while (true) {
        const ssize_t got = ::read(fd.get(), chunk, sizeof chunk);
        if (got < 0) {
            if (errno == EINTR) continue;
            throw InputError(path + ": cannot read (" + errno_text(errno) + ")");
        }
        if (got == 0) break;
        if (text.size() + static_cast<std::size_t>(got) > most) {
            if (regular) throw InputError(path + ": the file is larger than " + size_text(limit) + ", the most the project reads");
            throw InputError(path + ": more than " + size_text(most) + " came from this " + kind_of(fs::status(path).type()) +
                             ", the most the project reads from anything but a regular file");
        }
        text.append(chunk, static_cast<std::size_t>(got));
    }
    return text;
}

void check_output_path(const std::string& path) {
    if (path.empty()) throw UsageError("an output path is empty");
    std::error_code ec;
    const fs::file_status status = fs::symlink_status(path, ec);
    if (!ec && fs::exists(status) && !fs::is_regular_file(status)) {
        throw UsageError(path + ": exists and is a " + kind_of(status.type()) +
                         ", not a regular file; it is never replaced (choose another output)");
    }
    fs::path folder = fs::path(path).parent_path();
    if (folder.empty()) folder = ".";
    if (!fs::is_directory(folder, ec)) throw InputError(path + ": cannot write: the folder " + folder.string() + " does not exist");
    if (::access(folder.c_str(), W_OK) != 0) {
        throw InputError(path + ": cannot write into the folder " + folder.string() + " (" + errno_text(errno) + ")");
    }
}

void check_output_paths(const std::vector<std::string>& paths) {
    for (const std::string& p : paths) {
        if (!p.empty()) check_output_path(p);
    }
}

void write_text_file(const std::string& path, std::string_view text) {
    check_output_path(path);
    std::string temporary = path + ".XXXXXX.partial";
    const int fd_value = ::mkstemps(temporary.data(), 8);
    if (fd_value < 0) throw InputError(path + ": cannot create a file beside it (" + errno_text(errno) + ")");
    FileDescriptor fd(fd_value);
    auto fail = [&](const std::string& what, int error) {
        fd.close();
        ::unlink(temporary.c_str());
        throw InputError(path + ": " + what + " (" + errno_text(error) + ")");
    };
    if (::fchmod(fd.get(), new_file_mode()) != 0) fail("cannot set the new file's permissions", errno);
    std::size_t written = 0;
    while (written < text.size()) {
        const ssize_t n = ::write(fd.get(), text.data() + written, text.size() - written);
        if (n < 0) {
            if (errno == EINTR) continue;
            const int error = errno;
            fail(error == ENOSPC ? "write failed: the disk is full" : "write failed", error);
        }
        written += static_cast<std::size_t>(n);
    }
    // A full disk can show only when the data reaches it.
    if (::fdatasync(fd.get()) != 0) fail("write failed", errno);
    if (fd.close() != 0) fail("write failed", errno);
    if (::rename(temporary.c_str(), path.c_str()) != 0) {
        const int error = errno;
        ::unlink(temporary.c_str());
        throw InputError(path + ": cannot replace the file (" + errno_text(error) + ")");
    }
}

} // namespace ggg
