#include "io/safe_io.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cctype>
#include <cstdlib>
#include <cstring>
#include <dirent.h>
#include <signal.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace ml::io {

namespace {

std::string errnoText(int e) {
    return std::strerror(e);
}

// What a non-regular file is, for the message.
const char* kindName(mode_t mode) {
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
    if (S_ISSOCK(mode)) return "a socket";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISLNK(mode)) return "a symbolic link";
    return "not a regular file";
}

// Closes on scope exit; release() hands the descriptor over.
struct Fd {
    int fd = -1;
    explicit Fd(int f) : fd(f) {}
    ~Fd() {
        if (fd >= 0) ::close(fd);
    }
    Fd(const Fd&) = delete;
    Fd& operator=(const Fd&) = delete;
};

std::string parentOf(const std::string& path, std::string* base) {
    const size_t slash = path.find_last_of('/');
    if (slash == std::string::npos) {
        *base = path;
        return ".";
    }
    *base = path.substr(slash + 1);
    return slash == 0 ? "/" : path.substr(0, slash);
}

// This machine's name as it goes into temporary names: [A-Za-z0-9-] only, at most 32 characters, so
// that '.' stays the field separator ("host" when it has none usable).
const std::string& hostTag() {
    static const std::string tag = [] {
        char name[256] = {};
        std::string out;
        if (::gethostname(name, sizeof name - 1) == 0)
            for (const char* c = name; *c && out.size() < 32; ++c)
                if (std::isalnum(static_cast<unsigned char>(*c)) || *c == '-') out += *c;
        return out.empty() ? std::string("host") : out;
    }();
    return tag;
}

bool allOf(const std::string& s, const char* set) {
    return !s.empty() && s.find_first_not_of(set) == std::string::npos;
}

} // namespace

size_t removeStaleTemporaries(const std::string& path) {
    std::string base;
    const std::string dir = parentOf(path, &base);
    const std::string prefix = "." + base + ".tmp.";
    const std::string& host = hostTag();
    Fd d(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
    if (d.fd < 0) return 0;
    const int listed = ::dup(d.fd);
    DIR* listing = listed < 0 ? nullptr : ::fdopendir(listed);
    if (!listing) {
        if (listed >= 0) ::close(listed);
        return 0;
    }
    std::vector<std::string> stale;
    while (const dirent* e = ::readdir(listing)) {
        const std::string name = e->d_name;
        if (name.compare(0, prefix.size(), prefix) != 0) continue;
        // HOST.PID.HEX (this writer's names) or PID.HEX (names of writers before the host field).
        std::vector<std::string> fields;
        for (size_t at = prefix.size();;) {
            const size_t dot = name.find('.', at);
            fields.push_back(name.substr(at, dot == std::string::npos ? std::string::npos : dot - at));
            if (dot == std::string::npos) break;
            at = dot + 1;
        }
        if (fields.size() == 2) fields.insert(fields.begin(), host);
        if (fields.size() != 3 || fields[0] != host || !allOf(fields[1], "0123456789") ||
            fields[1].size() > 9 || !allOf(fields[2], "0123456789abcdef"))
            continue; // another machine's writer (a shared folder) or not our name: never touched
        const long pid = std::strtol(fields[1].c_str(), nullptr, 10);
        if (pid <= 0 || ::kill(pid_t(pid), 0) == 0 || errno != ESRCH) continue; // its writer may live
        struct stat st {};
        if (::fstatat(d.fd, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0 && S_ISREG(st.st_mode))
            stale.push_back(name);
    }
    ::closedir(listing);
    size_t removed = 0;
    for (const std::string& name : stale) removed += ::unlinkat(d.fd, name.c_str(), 0) == 0 ? 1 : 0;
    return removed;
}

Result<uint64_t> checkRegularFile(const std::string& path, uint64_t maxBytes) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) return fail(path + ": cannot open: " + errnoText(errno));
    if (!S_ISREG(st.st_mode))
        return fail(path + ": is " + std::string(kindName(st.st_mode)) + ", not a regular file");
    if (uint64_t(st.st_size) > maxBytes)
        return fail(path + ": " + std::to_string(uint64_t(st.st_size)) + " bytes, more than the " +
                    std::to_string(maxBytes) + "-byte limit");
    return uint64_t(st.st_size);
}

Result<uint64_t> readRegularFile(const std::string& path, uint64_t maxBytes,
                                 const std::function<unsigned char*(uint64_t size)>& destination) {
    if (auto c = checkRegularFile(path, maxBytes); !c) return fail(c.error());
    // O_NONBLOCK: if a FIFO replaced the file since the stat, the open returns at once, and the fstat
    // below refuses it. On a regular file the flag changes nothing.
    Fd fd(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY));
    if (fd.fd < 0) return fail(path + ": cannot open: " + errnoText(errno));
    struct stat st {};
    if (::fstat(fd.fd, &st) != 0) return fail(path + ": cannot stat: " + errnoText(errno));
    if (!S_ISREG(st.st_mode))
        return fail(path + ": is " + std::string(kindName(st.st_mode)) + ", not a regular file");
    const uint64_t size = uint64_t(st.st_size);
    if (size > maxBytes)
        return fail(path + ": " + std::to_string(size) + " bytes, more than the " + std::to_string(maxBytes) +
                    "-byte limit");
    unsigned char* out = destination(size);
    uint64_t done = 0;
    while (done < size) {
        const size_t want = size_t(std::min<uint64_t>(size - done, uint64_t(1) << 30));
        const ssize_t got = ::read(fd.fd, out + done, want);
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) return fail(path + ": read failed: " + errnoText(errno));
        if (got == 0) return fail(path + ": file shrank while it was read");
        done += uint64_t(got);
    }
    return size;
}

Result<std::vector<unsigned char>> readRegularFileHead(const std::string& path, size_t bytes,
                                                       uint64_t* fileSize) {
    if (auto c = checkRegularFile(path); !c) return fail(c.error());
    Fd fd(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY));
    if (fd.fd < 0) return fail(path + ": cannot open: " + errnoText(errno));
    struct stat st {};
    if (::fstat(fd.fd, &st) != 0) return fail(path + ": cannot stat: " + errnoText(errno));
    if (!S_ISREG(st.st_mode))
        return fail(path + ": is " + std::string(kindName(st.st_mode)) + ", not a regular file");
    *fileSize = uint64_t(st.st_size);
    std::vector<unsigned char> head(size_t(std::min<uint64_t>(bytes, uint64_t(st.st_size))));
    size_t done = 0;
    while (done < head.size()) {
        const ssize_t got = ::read(fd.fd, head.data() + done, head.size() - done);
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) return fail(path + ": read failed: " + errnoText(errno));
        if (got == 0) return fail(path + ": file shrank while it was read");
        done += size_t(got);
    }
    return head;
}

Result<std::vector<unsigned char>> readRegularFile(const std::string& path, uint64_t maxBytes) {
    std::vector<unsigned char> bytes;
    auto r = readRegularFile(path, maxBytes, [&](uint64_t size) {
        bytes.resize(size_t(size));
        return bytes.data();
    });
    if (!r) return fail(r.error());
    return bytes;
}

Result<void> checkReplaceable(const std::string& path) {
    if (path.empty()) return fail("output path is empty");
    if (path.back() == '/') return fail(path + ": names a directory, not a file");
    struct stat target {};
    if (::lstat(path.c_str(), &target) == 0) {
        if (!S_ISREG(target.st_mode))
            return fail(path + ": exists and is " + std::string(kindName(target.st_mode)) +
                        "; refusing to replace it");
    } else if (errno != ENOENT) {
        return fail(path + ": " + errnoText(errno));
    }
    return {};
}

Result<void> writeFileAtomically(const std::string& path, const void* data, size_t bytes) {
    if (path.empty()) return fail("output path is empty");
    if (path.back() == '/') return fail(path + ": names a directory, not a file");
    struct stat target {};
    bool exists = false;
    if (::lstat(path.c_str(), &target) == 0) {
        exists = true;
        if (!S_ISREG(target.st_mode))
            return fail(path + ": exists and is " + std::string(kindName(target.st_mode)) +
                        "; refusing to replace it");
    } else if (errno != ENOENT) {
        return fail(path + ": " + errnoText(errno));
    }
    std::string base;
    const std::string dir = parentOf(path, &base);
    (void)removeStaleTemporaries(path); // left by a writer of this target that died (kill -9, power loss)

    // A fresh name per try: pid, a process-wide counter and the clock. O_EXCL makes a name that exists
    // (left over, or planted as a symlink) fail with EEXIST, and we try the next one.
    static std::atomic<uint64_t> counter{0};
    const std::string& host = hostTag();
    std::string tmp;
    int raw = -1;
    for (int attempt = 0; attempt < 64 && raw < 0; ++attempt) {
        const uint64_t tick = uint64_t(std::chrono::steady_clock::now().time_since_epoch().count());
        char suffix[96];
        std::snprintf(suffix, sizeof suffix, ".tmp.%s.%ld.%llx", host.c_str(), long(::getpid()),
                      (unsigned long long)((tick * 0x9E3779B97F4A7C15ull) ^ counter.fetch_add(1)));
        tmp = dir + "/." + base + suffix;
        raw = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC | O_NOCTTY, 0666);
        if (raw < 0 && errno != EEXIST)
            return fail(path + ": cannot create a temporary file in " + dir + ": " + errnoText(errno));
    }
    if (raw < 0) return fail(path + ": cannot find a free temporary name in " + dir);
    Fd fd(raw);
    auto abandon = [&](const std::string& why) {
        ::close(fd.fd);
        fd.fd = -1;
        ::unlink(tmp.c_str());
        return fail(path + ": " + why);
    };
    if (exists) (void)::fchmod(fd.fd, target.st_mode & 0777); // keep the old file's permissions
    const unsigned char* p = static_cast<const unsigned char*>(data);
    size_t done = 0;
    while (done < bytes) {
        const ssize_t put = ::write(fd.fd, p + done, std::min<size_t>(bytes - done, size_t(1) << 30));
        if (put < 0 && errno == EINTR) continue;
        if (put <= 0) return abandon("write failed: " + errnoText(put < 0 ? errno : EIO));
        done += size_t(put);
    }
    if (::fsync(fd.fd) != 0) return abandon("fsync failed: " + errnoText(errno));
    const int closed = ::close(fd.fd);
    fd.fd = -1;
    if (closed != 0) {
        const int e = errno;
        ::unlink(tmp.c_str());
        return fail(path + ": close failed: " + errnoText(e));
    }
    // rename() replaces the directory entry itself: even if `path` became a symlink since the lstat,
    // nothing is written through it.
    if (::rename(tmp.c_str(), path.c_str()) != 0) {
        const int e = errno;
        ::unlink(tmp.c_str());
        return fail(path + ": cannot rename the temporary file over it: " + errnoText(e));
    }
    // Make the rename itself durable (best effort: some file systems refuse fsync on a directory).
    Fd d(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
    if (d.fd >= 0) (void)::fsync(d.fd);
    return {};
}

std::string escapeText(std::string_view text, size_t maxBytes) {
    std::string out;
    out.reserve(std::min(text.size(), maxBytes) + 16);
    size_t i = 0;
    for (; i < text.size(); ++i) {
        const unsigned char c = static_cast<unsigned char>(text[i]);
        // Cut only at the start of a character (not inside a UTF-8 sequence).
        if (out.size() >= maxBytes && (c < 0x80 || c >= 0xC0)) break;
        char buf[8];
        if (c == '\n') {
            out += "\\n";
        } else if (c == '\r') {
            out += "\\r";
        } else if (c == '\t') {
            out += "\\t";
        } else if (c < 0x20 || c == 0x7F) {
            std::snprintf(buf, sizeof buf, "\\x%02x", c);
            out += buf;
        } else if (c == 0xC2 && i + 1 < text.size() && static_cast<unsigned char>(text[i + 1]) >= 0x80 &&
                   static_cast<unsigned char>(text[i + 1]) <= 0x9F) {
            // U+0080..U+009F: C1 controls (CSI is U+009B on some terminals).
            std::snprintf(buf, sizeof buf, "\\u%04x", unsigned(static_cast<unsigned char>(text[i + 1])));
            out += buf;
            ++i;
        } else {
            out += char(c);
        }
    }
    if (i < text.size()) out += "... (" + std::to_string(text.size()) + " bytes)";
    return out;
}

} // namespace ml::io
