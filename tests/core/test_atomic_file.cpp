// writeFileAtomic: the file appears whole, replaces what was there, leaves no temporary behind,
// and fails with RuntimeError (and no debris) where it cannot write.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <csignal>

#include <sys/resource.h>
#include <unistd.h>

#include "core/atomic_file.h"
#include "core/error.h"

namespace cavesim {
namespace {

namespace fs = std::filesystem;

/// A fresh directory under the system temporary directory, removed at the end of the test.
struct TempDir {
    fs::path path;
    TempDir() {
        path = fs::temp_directory_path() / ("cavesim_test_core_" + std::to_string(::getpid()) + "_" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::permissions(path, fs::perms::owner_all, fs::perm_options::add, ec);
        fs::remove_all(path, ec);
    }
};

std::string readAll(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

/// Names in `dir`, sorted.
std::vector<std::string> entries(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

TEST(AtomicFile, WritesTheText) {
    TempDir dir;
    const fs::path p = dir.path / "a.txt";
    const std::string text = std::string("line 1\nline 2\n") + std::string(1, '\0') + "binary\xff";
    writeFileAtomic(p.string(), text);
    EXPECT_EQ(readAll(p), text);
    EXPECT_EQ(entries(dir.path), std::vector<std::string>{"a.txt"});  // no temporary left
}

TEST(AtomicFile, WritesAnEmptyFile) {
    TempDir dir;
    const fs::path p = dir.path / "empty";
    writeFileAtomic(p.string(), "");
    EXPECT_TRUE(fs::is_regular_file(p));
    EXPECT_EQ(fs::file_size(p), 0u);
}

TEST(AtomicFile, ReplacesAnExistingFileWhole) {
    TempDir dir;
    const fs::path p = dir.path / "a.txt";
    writeFileAtomic(p.string(), std::string(10000, 'x'));
    writeFileAtomic(p.string(), "short");
    EXPECT_EQ(readAll(p), "short");  // no tail of the longer old content
    EXPECT_EQ(entries(dir.path), std::vector<std::string>{"a.txt"});
}

TEST(AtomicFile, ReplacesASymlinkInsteadOfFollowingIt) {
    TempDir dir;
    const fs::path target = dir.path / "target.txt";
    const fs::path link = dir.path / "link.txt";
    writeFileAtomic(target.string(), "original");
    fs::create_symlink(target, link);
    writeFileAtomic(link.string(), "new");
    EXPECT_FALSE(fs::is_symlink(link));
    EXPECT_EQ(readAll(link), "new");
    EXPECT_EQ(readAll(target), "original");
}

TEST(AtomicFile, FailsIntoAMissingDirectory) {
    TempDir dir;
    EXPECT_THROW(writeFileAtomic((dir.path / "no" / "such" / "dir" / "a.txt").string(), "x"), RuntimeError);
    EXPECT_TRUE(entries(dir.path).empty());
}

TEST(AtomicFile, FailsWhenTheParentIsAFile) {
    TempDir dir;
    writeFileAtomic((dir.path / "file").string(), "x");
    EXPECT_THROW(writeFileAtomic((dir.path / "file" / "a.txt").string(), "y"), RuntimeError);
    EXPECT_EQ(entries(dir.path), std::vector<std::string>{"file"});
}

TEST(AtomicFile, FailsOntoADirectoryAndRemovesItsTemporary) {
    TempDir dir;
    fs::create_directory(dir.path / "taken");
    fs::create_directory(dir.path / "taken" / "inside");  // a non-empty directory: rename must fail
    EXPECT_THROW(writeFileAtomic((dir.path / "taken").string(), "x"), RuntimeError);
    EXPECT_EQ(entries(dir.path), std::vector<std::string>{"taken"});  // the temporary was removed
    EXPECT_TRUE(fs::is_directory(dir.path / "taken" / "inside"));
}

TEST(AtomicFile, FailsIntoAReadOnlyDirectory) {
    if (::geteuid() == 0) GTEST_SKIP() << "root ignores directory permissions";
    TempDir dir;
    fs::permissions(dir.path, fs::perms::owner_read | fs::perms::owner_exec, fs::perm_options::replace);
    EXPECT_THROW(writeFileAtomic((dir.path / "a.txt").string(), "x"), RuntimeError);
    fs::permissions(dir.path, fs::perms::owner_all, fs::perm_options::add);
    EXPECT_TRUE(entries(dir.path).empty());
}

// A file-size limit cuts the write short: the error names the file, the reason and how far it got;
// the old file stays as it was and no temporary is left behind.
TEST(AtomicFile, AShortWriteIsAnErrorAndLeavesTheOldFile) {
    TempDir dir;
    const fs::path p = dir.path / "state.bin";
    writeFileAtomic(p.string(), "old");
    struct rlimit old {};
    ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
    void (*previous)(int) = std::signal(SIGXFSZ, SIG_IGN);  // EFBIG instead of the signal
    struct rlimit small = old;
    small.rlim_cur = 4096;
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
    std::string message;
    try {
        writeFileAtomic(p.string(), std::string(10000, 'x'));
    } catch (const RuntimeError& e) {
        message = e.what();
    }
    ::setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, previous);
    EXPECT_NE(message.find("cannot write " + p.string()), std::string::npos) << message;
    EXPECT_NE(message.find("File too large"), std::string::npos) << message;
    EXPECT_NE(message.find("4096 of 10000 bytes"), std::string::npos) << message;
    EXPECT_EQ(readAll(p), "old");
    EXPECT_EQ(entries(dir.path), std::vector<std::string>{"state.bin"});
}

TEST(AtomicFile, WritesPiecesInOrderAndCountsShortWritesOverAllOfThem) {
    TempDir dir;
    const fs::path p = dir.path / "pieces.bin";
    const std::string grid(3000, 'g');
    const std::uint64_t size = grid.size();
    writeFileAtomic(p.string(), {"head_", std::string_view(reinterpret_cast<const char*>(&size), sizeof size), grid,
                                 std::string_view(), "_tail"});
    EXPECT_EQ(readAll(p), "head_" + std::string(reinterpret_cast<const char*>(&size), sizeof size) + grid + "_tail");
    EXPECT_EQ(entries(dir.path), std::vector<std::string>{"pieces.bin"});
    // A file-size limit inside the second piece: an error counting the bytes of all the pieces.
    struct rlimit old {};
    ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
    void (*previous)(int) = std::signal(SIGXFSZ, SIG_IGN);
    struct rlimit small = old;
    small.rlim_cur = 4096;
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
    std::string message;
    try {
        writeFileAtomic(p.string(), {std::string(3000, 'a'), std::string(3000, 'b'), std::string(3000, 'c')});
    } catch (const RuntimeError& e) {
        message = e.what();
    }
    ::setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, previous);
    EXPECT_NE(message.find("4096 of 9000 bytes"), std::string::npos) << message;
    EXPECT_EQ(readAll(p).size(), 3000u + sizeof size + 5 + 5);  // the old file, whole
    EXPECT_EQ(entries(dir.path), std::vector<std::string>{"pieces.bin"});
}

TEST(AtomicFile, SyncDirectoryNamesAFolderThatIsNotThere) {
    TempDir dir;
    EXPECT_NO_THROW(syncDirectory(dir.path));
    EXPECT_THROW(syncDirectory(dir.path / "missing"), RuntimeError);
}

}  // namespace
}  // namespace cavesim
