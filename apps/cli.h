// Command-line parsing shared by the subcommands: --flag value pairs and bare --switches, with
// one-line errors naming the flag and the reason.
#pragma once
#include "manylights/result.h"

#include <array>
#include <cstdint>
#include <initializer_list>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace ml::cli {

struct Args {
    std::map<std::string, std::string> values;
    std::set<std::string> switches;
    bool help = false;

    bool has(const std::string& flag) const { return values.count(flag) || switches.count(flag); }
    std::string get(const std::string& flag, const std::string& fallback) const {
        auto it = values.find(flag);
        return it == values.end() ? fallback : it->second;
    }
};

// The flags of a command or of an option group (apps/options.h): `valued` take a value, `switches` none.
struct Flags {
    std::set<std::string> valued, switches;
};

// `valued` flags take a value; `switches` take none. Anything else is an error, and so is a flag given
// twice or a valued flag whose next argument is one of the flags (its value is missing).
Result<Args> parse(int argc, char** argv, int first, const std::set<std::string>& valued,
                   const std::set<std::string>& switches);
// A command's option groups and its own flags together. A name in two of them is refused (the
// command's flag would silently take over the group's parse), before any argument is read.
Result<Args> parse(int argc, char** argv, int first, std::initializer_list<Flags> groups);
Result<uint32_t> parseUint(const std::string& flag, const std::string& text, uint32_t lo, uint32_t hi);
Result<std::pair<uint32_t, uint32_t>> parseSize(const std::string& flag, const std::string& text);
Result<void> makeDirectory(const std::string& path);
// Output paths checked before any heavy work: a file's folder is created (or refused) and the file must
// be replaceable (io::checkReplaceable); a folder is created. One line naming the flag.
Result<void> checkOutputFile(const std::string& flag, const std::string& path);
Result<void> checkOutputDirectory(const std::string& flag, const std::string& path);
// "X,Y,Z,TX,TY,TZ": camera position and target (six numbers, comma-separated).
Result<std::array<float, 6>> parseCamera(const std::string& flag, const std::string& text);

} // namespace ml::cli
