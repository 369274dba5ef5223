// The shared scenes (sample-building.gltf, fzk-haus.glb): in ML_SHARED_DIR when it is set, else in
// ../shared beside the checkout, where CI has them. A clone elsewhere has no shared folder; there the
// tests that load these scenes skip (ctest reports them as Skipped, naming the folder) rather than fail
// on a missing file. Where the folder exists, a missing or broken scene still fails its test.
#pragma once
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace ml::test {

inline std::string sharedDir() {
    const char* env = std::getenv("ML_SHARED_DIR");
    return env && *env ? std::string(env) : std::string(ML_SOURCE_DIR) + "/../shared";
}
inline std::string sharedScenePath(const char* name) {
    return sharedDir() + "/scenes/" + name;
}
inline bool haveSharedDir() {
    return std::filesystem::is_directory(sharedDir());
}

} // namespace ml::test

// At the top of a test that loads a shared scene: skips it (returns) when the shared folder is absent.
#define ML_SKIP_WITHOUT_SHARED()                                                                             \
    do {                                                                                                     \
        if (!::ml::test::haveSharedDir())                                                                    \
            GTEST_SKIP() << "no shared folder at " << ::ml::test::sharedDir() << " (set ML_SHARED_DIR)";     \
    } while (0)
