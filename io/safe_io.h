// File input and output for untrusted paths and untrusted bytes (docs/reliability.md, "Untrusted files").
//
// Reading: only regular files. A directory, FIFO, socket or device given as a scene or bake file gets a
// one-line error instead of a huge allocation (tellg() on a directory), a hang (a FIFO with no writer)
// or an endless read (/dev/zero). stat() names the problem first; the open is O_NONBLOCK so a FIFO
// swapped in after the stat cannot block, and fstat() on the open descriptor is what decides.
//
// Writing: writeFileAtomically is the one place that writes an output file. It creates a temporary
// beside the target exclusively (O_CREAT | O_EXCL | O_NOFOLLOW, a fresh name each try), checks every
// write, fsync and close, and renames it over the target. It refuses a target that exists and is not a
// regular file (a symbolic link, a directory, /dev/full...), so it never writes through a link and
// never replaces a device node. A failed write leaves the old target untouched and no temporary behind;
// a writer that is killed leaves its temporary (.NAME.tmp.HOST.PID.N), and the next write of the same
// target removes it once that process is gone (removeStaleTemporaries).
//
// Printing: escapeText makes bytes from a file (scene names, mesh names, parser messages) safe for a
// one-line message: control characters become \n, \t, \xNN (C1 controls \u0080..\u009f too), and long
// text is cut with a byte count, so a file cannot add lines or terminal escape codes to our output.
#pragma once
#include "manylights/result.h"

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace ml::io {

// "<path>: <reason>" when `path` is missing, not a regular file, or larger than maxBytes.
// Returns the file's size in bytes.
Result<uint64_t> checkRegularFile(const std::string& path, uint64_t maxBytes = UINT64_MAX);

// Reads a whole regular file of at most maxBytes. `destination(size)` is called once with the file's
// size and returns where to put its bytes (size bytes of room); this lets the caller read straight
// into a word vector. Errors are one line: "<path>: <reason>".
Result<uint64_t> readRegularFile(const std::string& path, uint64_t maxBytes,
                                 const std::function<unsigned char*(uint64_t size)>& destination);
Result<std::vector<unsigned char>> readRegularFile(const std::string& path, uint64_t maxBytes = UINT64_MAX);
// The first min(size, bytes) bytes of a regular file, and its whole size in *fileSize: lets a reader
// check a header before it allocates room for the whole file.
Result<std::vector<unsigned char>> readRegularFileHead(const std::string& path, size_t bytes,
                                                       uint64_t* fileSize);

// Whether writeFileAtomically may write `path`: it does not exist, or it is a regular file (not a
// symlink, folder or device). Lets a command refuse before a long computation, not after it.
Result<void> checkReplaceable(const std::string& path);

// Removes the temporaries that writers of `path` on this machine left when they died (".NAME.tmp.HOST.PID.*"
// whose process is gone, regular files only); returns how many. writeFileAtomically calls it first, so
// a bake killed mid-write leaves no 100 MB file behind for long. Temporaries of live writers and of
// other machines (a shared folder of a bake farm) are never touched.
size_t removeStaleTemporaries(const std::string& path);

// See the overview. Errors: "<path>: <reason>".
Result<void> writeFileAtomically(const std::string& path, const void* data, size_t bytes);
inline Result<void> writeFileAtomically(const std::string& path, std::string_view text) {
    return writeFileAtomically(path, text.data(), text.size());
}

// Escapes control characters and cuts the text to about maxBytes (see the overview).
std::string escapeText(std::string_view text, size_t maxBytes = 300);

} // namespace ml::io
