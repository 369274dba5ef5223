// Hostile paths: a folder, a FIFO or a device where a file is expected,
// output targets that are symlinks, devices or folders, a symlink planted at the old predictable
// temporary name, a failing write (file size limit), and control characters in printed text.
#include "hostile_test_util.h"

#include "io/safe_io.h"
#include "scenes/scenes.h"

#include <gtest/gtest.h>

#include <csignal>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

namespace ml {
namespace {

using hostile::tempDir;

std::string fresh(const std::string& name) {
    const std::string p = (tempDir() / name).string();
    std::error_code ignored;
    std::filesystem::remove_all(p, ignored);
    return p;
}
std::string makeFifo(const std::string& name) {
    const std::string p = fresh(name);
    EXPECT_EQ(::mkfifo(p.c_str(), 0600), 0);
    return p;
}
std::string makeDir(const std::string& name) {
    const std::string p = fresh(name);
    std::filesystem::create_directories(p);
    return p;
}
void expectOneLine(const std::string& message, const std::string& needle) {
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_NE(message.find(needle), std::string::npos) << message;
}
// The only entries of the temp folder whose names start with `prefix` (no temporary left behind).
size_t entriesStartingWith(const std::string& prefix) {
    size_t n = 0;
    for (const auto& e : std::filesystem::directory_iterator(tempDir()))
        n += e.path().filename().string().rfind(prefix, 0) == 0;
    return n;
}

TEST(HostileRead, FolderFifoAndDeviceAreRefused) {
    const std::string dir = makeDir("folder.mlbk"), fifo = makeFifo("pipe.mlbk");
    for (const std::string& p : {dir, fifo, std::string("/dev/zero")}) {
        auto r = io::readRegularFile(p);
        ASSERT_FALSE(r.ok()) << p;
        expectOneLine(r.error(), "not a regular file");
        auto b = readBakeFile(p); // would have been bad_alloc (folder) or a hang (FIFO)
        ASSERT_FALSE(b.ok());
        expectOneLine(b.error(), p + ": is ");
    }
    const std::string gltfDir = makeDir("folder.gltf"), gltfFifo = makeFifo("pipe.glb");
    for (const std::string& p : {gltfDir, gltfFifo}) {
        auto s = loadScene(p, 4, 1);
        ASSERT_FALSE(s.ok());
        expectOneLine(s.error(), "not a regular file");
    }
    auto missing = io::readRegularFile((tempDir() / "missing").string());
    ASSERT_FALSE(missing.ok());
    expectOneLine(missing.error(), "No such file");
}

// A sparse file claims terabytes without using the disk: an error line, not an abort (bad_alloc).
// (A header that states the terabytes too gets "too large to read into memory" where the allocation
// fails; ASan aborts on such a request instead, so that case is not run here.)
TEST(HostileRead, SparseHugeBakeFile) {
    const std::string p = fresh("sparse.mlbk");
    // A real header (magic, version) stating a small size: refused before anything is allocated.
    std::vector<uint32_t> header(16, 0u);
    header[bakefmt::kHMagic] = bakefmt::kMagic, header[bakefmt::kHVersion] = bakefmt::kVersion;
    header[bakefmt::kHTotalLo] = 16;
    hostile::writeBytes(p, std::string(reinterpret_cast<const char*>(header.data()), 64));
    if (::truncate(p.c_str(), off_t(1) << 42) != 0) GTEST_SKIP() << "file system refuses a 4 TiB sparse file";
    auto r = readBakeFile(p);
    ASSERT_FALSE(r.ok());
    expectOneLine(r.error(), p + ": header: file should be 16 words but is ");
    std::filesystem::remove(p);
}

TEST(HostileRead, SizeLimit) {
    const std::string p = fresh("big.bin");
    hostile::writeBytes(p, std::string(100, 'x'));
    EXPECT_TRUE(io::readRegularFile(p, 100).ok());
    auto r = io::readRegularFile(p, 99);
    ASSERT_FALSE(r.ok());
    expectOneLine(r.error(), "limit");
}

TEST(HostileWrite, ReplacesRegularFileAtomically) {
    const std::string p = fresh("out.bin");
    ASSERT_TRUE(io::writeFileAtomically(p, std::string("first")).ok());
    ASSERT_EQ(::chmod(p.c_str(), 0640), 0);
    ASSERT_TRUE(io::writeFileAtomically(p, std::string("second")).ok());
    EXPECT_EQ(hostile::readBytes(p), "second");
    struct stat st {};
    ASSERT_EQ(::stat(p.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0640u) << "the old file's permissions are kept";
    EXPECT_EQ(entriesStartingWith(".out.bin"), 0u) << "no temporary left behind";
}

TEST(HostileWrite, RefusesNonRegularTargets) {
    const std::string victim = fresh("victim.txt");
    hostile::writeBytes(victim, "precious");
    const std::string link = fresh("link.mlbk");
    ASSERT_EQ(::symlink(victim.c_str(), link.c_str()), 0);
    const std::string dir = makeDir("dir.mlbk"), fifo = makeFifo("fifo.mlbk");
    for (const std::string& target : {link, dir, fifo}) {
        auto r = io::writeFileAtomically(target, std::string("payload"));
        ASSERT_FALSE(r.ok()) << target;
        expectOneLine(r.error(), "refusing to replace it");
    }
    EXPECT_EQ(hostile::readBytes(victim), "precious");
    struct stat st {};
    ASSERT_EQ(::lstat(link.c_str(), &st), 0);
    EXPECT_TRUE(S_ISLNK(st.st_mode));
    ASSERT_EQ(::lstat(fifo.c_str(), &st), 0);
    EXPECT_TRUE(S_ISFIFO(st.st_mode));
    // The same through the bake-file writer (what `bake --out` calls).
    auto bw = writeBakeFile(link, hostile::syntheticBake(StaticMethod::SM, 1));
    ASSERT_FALSE(bw.ok());
    expectOneLine(bw.error(), "symbolic link");
    EXPECT_EQ(hostile::readBytes(victim), "precious");
    // A path ending in '/' names a folder.
    EXPECT_FALSE(io::writeFileAtomically(dir + "/", std::string("x")).ok());
}

// The old writer wrote PATH.tmp, following a symlink an attacker planted there.
TEST(HostileWrite, PlantedTemporaryIsNotFollowed) {
    const std::string victim = fresh("victim2.txt"), out = fresh("planted.mlbk");
    hostile::writeBytes(victim, "precious");
    ASSERT_EQ(::symlink(victim.c_str(), (out + ".tmp").c_str()), 0);
    ASSERT_TRUE(writeBakeFile(out, hostile::syntheticBake(StaticMethod::MH, 1)).ok());
    EXPECT_EQ(hostile::readBytes(victim), "precious");
    EXPECT_TRUE(readBakeFile(out).ok());
}

// A writer killed mid-write (here by the file size limit's SIGXFSZ, as kill -9 or a power cut would)
// leaves its temporary; the next write of the same target removes it once that process is gone. Those
// of a live writer, of another machine (a shared folder) and anything not a regular file stay.
TEST(HostileWrite, KilledWritersTemporaryIsRemovedByTheNextWrite) {
    const std::string p = fresh("killed.bin");
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        struct rlimit small {
            1000, 1000
        }, none{0, 0};
        ::setrlimit(RLIMIT_CORE, &none);
        ::setrlimit(RLIMIT_FSIZE, &small);
        std::signal(SIGXFSZ, SIG_DFL);
        (void)io::writeFileAtomically(p, std::string(4000, 'y'));
        ::_exit(0); // not reached: SIGXFSZ ends the writer inside write()
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGXFSZ) << status;
    ASSERT_EQ(entriesStartingWith(".killed.bin.tmp."), 1u);

    const std::string dir = tempDir().string(), live = std::to_string(::getpid());
    const std::string dead = std::to_string(child); // reaped above: no such process now
    hostile::writeBytes(dir + "/.killed.bin.tmp." + live + ".1f", "a live writer's (older name form)");
    hostile::writeBytes(dir + "/.killed.bin.tmp.otherhost." + dead + ".2f", "another machine's");
    ASSERT_EQ(::symlink("/nonexistent", (dir + "/.killed.bin.tmp." + dead + ".3f").c_str()), 0);
    ASSERT_TRUE(io::writeFileAtomically(p, std::string("new")).ok());
    EXPECT_EQ(hostile::readBytes(p), "new");
    EXPECT_EQ(entriesStartingWith(".killed.bin.tmp."), 3u) << "only the dead writer's temporary goes";
    EXPECT_TRUE(std::filesystem::exists(dir + "/.killed.bin.tmp." + live + ".1f"));
    EXPECT_TRUE(std::filesystem::exists(dir + "/.killed.bin.tmp.otherhost." + dead + ".2f"));
    EXPECT_EQ(io::removeStaleTemporaries(p), 0u);
    for (const auto& e : std::filesystem::directory_iterator(tempDir()))
        if (e.path().filename().string().rfind(".killed.bin.tmp.", 0) == 0) std::filesystem::remove(e.path());
}

// A write that fails part-way (here: the file size limit, as a full disk would) is reported, the old
// target is untouched and the temporary is removed.
TEST(HostileWrite, FailedWriteKeepsOldTarget) {
    const std::string p = fresh("limited.bin");
    ASSERT_TRUE(io::writeFileAtomically(p, std::string("old")).ok());
    struct rlimit saved {};
    ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &saved), 0);
    auto oldHandler = std::signal(SIGXFSZ, SIG_IGN);
    struct rlimit small = saved;
    small.rlim_cur = 1000;
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
    auto r = io::writeFileAtomically(p, std::string(4000, 'y'));
    ::setrlimit(RLIMIT_FSIZE, &saved);
    std::signal(SIGXFSZ, oldHandler);
    ASSERT_FALSE(r.ok());
    expectOneLine(r.error(), "write failed");
    EXPECT_EQ(hostile::readBytes(p), "old");
    EXPECT_EQ(entriesStartingWith(".limited.bin"), 0u);
}

TEST(HostileText, EscapeText) {
    EXPECT_EQ(io::escapeText("plain name-1.glb"), "plain name-1.glb");
    EXPECT_EQ(io::escapeText("a\nb\rc\td"), "a\\nb\\rc\\td");
    EXPECT_EQ(io::escapeText(std::string("\x1b[31mred\x7f", 9)), "\\x1b[31mred\\x7f");
    EXPECT_EQ(io::escapeText("\xc2\x9b"
                             "2J"),
              "\\u009b2J");                                  // C1 CSI
    EXPECT_EQ(io::escapeText("caf\xc3\xa9"), "caf\xc3\xa9"); // UTF-8 text stays
    const std::string cut = io::escapeText(std::string(1000, 'z'), 50);
    EXPECT_EQ(cut, std::string(50, 'z') + "... (1000 bytes)");
    EXPECT_EQ(io::escapeText(std::string("\0x", 2)), "\\x00x");
}

// The command line on the same inputs: exit 2 and one line, never an abort or a hang.
TEST(HostileCli, FolderAndFifoAsBakeFileOrScene) {
    const std::string dir = makeDir("cli_folder.mlbk"), fifo = makeFifo("cli_pipe.mlbk");
    const std::string sceneFifo = makeFifo("cli_pipe.gltf");
    const std::string commands[] = {
        "inspect " + dir,
        "verify " + dir,
        "inspect " + fifo,
        "verify " + fifo,
        "bake --method mh --res 64 --lights 0 --renderer cpu --quiet --scene " + sceneFifo + " --out " +
            (tempDir() / "never.mlbk").string(),
    };
    for (const std::string& c : commands) {
        auto r = hostile::runCli(c, 20);
        EXPECT_EQ(r.status, 2) << c << ": " << r.err;
        ASSERT_FALSE(r.err.empty()) << c;
        EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << c << ": " << r.err;
        EXPECT_NE(r.err.find("not a regular file"), std::string::npos) << c << ": " << r.err;
    }
}

// demo on a hostile or malformed file exits 2 like bake, inspect and verify (it used to exit 1), with
// one line; a usage error exits 1 (README "Exit status").
TEST(HostileCli, DemoExitsTwoOnHostileFiles) {
    const std::string gltf = fresh("demo_escape.gltf"), bake = fresh("demo_damaged.mlbk");
    hostile::writeBytes(gltf, hostile::tetraJson("\"uri\": \"../../../../../../../../etc/passwd\""));
    hostile::writeBytes(bake, "MLBK this is not a bake file");
    const std::string out = " --frames 1 --size 32x32 --lights 4 --out " + (tempDir() / "demo_out").string();
    const std::pair<std::string, int> cases[] = {
        {"demo --scene " + gltf + out, 2},
        {"demo --scene " + fresh("demo_missing.glb") + out, 2},
        {"demo --bake " + bake + out, 2},
        {"demo --frames 1 --frames 2" + out, 1},
    };
    for (const auto& [c, status] : cases) {
        auto r = hostile::runCli(c, 120);
        EXPECT_EQ(r.status, status) << c << ": " << r.err;
        ASSERT_FALSE(r.err.empty()) << c;
        // The refusal is the last line (the module's device notes may come before it).
        const size_t last = r.err.rfind('\n', r.err.size() - 2);
        const std::string line = r.err.substr(last == std::string::npos ? 0 : last + 1);
        EXPECT_EQ(line.find("manylights demo: "), 0u) << c << ": " << r.err;
        EXPECT_EQ(line.back(), '\n') << c << ": " << r.err;
    }
}

TEST(HostileCli, BakeOutRefusesSymlinkAndDevice) {
    const std::string victim = fresh("cli_victim.txt"), link = fresh("cli_link.mlbk");
    hostile::writeBytes(victim, "precious");
    ASSERT_EQ(::symlink(victim.c_str(), link.c_str()), 0);
    const std::string fifo = makeFifo("cli_out_fifo.mlbk");
    for (const std::string& out : {link, fifo}) {
        auto r =
            hostile::runCli("bake --method sm --res 16 --lights 0 --renderer cpu --quiet --out " + out, 60);
        EXPECT_EQ(r.status, 1) << r.err; // --out refused before the bake starts: a usage error
        EXPECT_NE(r.err.find("refusing to replace it"), std::string::npos) << r.err;
        EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
    }
    EXPECT_EQ(hostile::readBytes(victim), "precious");
}

} // namespace
} // namespace ml
