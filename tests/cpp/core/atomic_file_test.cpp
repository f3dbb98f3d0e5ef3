// Atomic output files never replace anything but a regular file: devices, FIFOs,
// sockets and folders are refused with an IoError naming the path and left as they were; a
// symbolic link to a regular file is written through (the link stays, its target is replaced).
#include "curvedslicer/core/atomic_file.hpp"

#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "common/test_paths.hpp"
#include "curvedslicer/core/error.hpp"

namespace curvedslicer {
namespace {

namespace fs = std::filesystem;

std::string readText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The message of the IoError writeTextFileAtomically(path, "new") throws ("" if none).
std::string writeError(const fs::path& path) {
  try {
    writeTextFileAtomically(path, "new");
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

::testing::AssertionResult contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "'" << text << "' does not contain '" << part << "'";
}

/// Nothing but the listed entries in `dir` (no temporary file left behind).
std::size_t entryCount(const fs::path& dir) {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++n;
  return n;
}

TEST(AtomicFile, RegularFilesAndNewPathsAreWritten) {
  const fs::path dir = testing::freshTempDir();
  writeTextFileAtomically(dir / "a.txt", "one");
  writeTextFileAtomically(dir / "a.txt", "two");
  EXPECT_EQ(readText(dir / "a.txt"), "two");
  EXPECT_EQ(resolveOutputPath(dir / "a.txt"), dir / "a.txt");
  EXPECT_EQ(resolveOutputPath(dir / "missing.txt"), dir / "missing.txt");
  EXPECT_EQ(entryCount(dir), 1u);
}

TEST(AtomicFile, NamesUpToTheFileSystemsLimitAreWritten) {
  // the temporary file "NAME.tmp-PID-N" must not push a long name past NAME_MAX
  const fs::path dir = testing::freshTempDir();
  const std::string longest(255, 'a');
  writeTextFileAtomically(dir / longest, "one");
  EXPECT_EQ(readText(dir / longest), "one");
  EXPECT_EQ(entryCount(dir), 1u);
  try {
    writeTextFileAtomically(dir / std::string(300, 'b'), "two");
    ADD_FAILURE() << "a 300-byte name was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_TRUE(contains(e.what(),
                         "output file name is 300 bytes long, more than the 255 the "
                         "file system allows: 'bbbb"));
  }
  EXPECT_EQ(entryCount(dir), 1u);
}

TEST(AtomicFile, TemporariesOfKilledRunsAreRemovedByTheNextWrite) {
  const fs::path dir = testing::freshTempDir();
  // a process that has ended: its pid names no process any more
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ASSERT_GT(child, 0);
  ASSERT_EQ(::waitpid(child, nullptr, 0), child);
  const std::string dead = std::to_string(child), alive = std::to_string(::getpid());
  for (const std::string name :
       {"a.txt.tmp-" + dead + "-0", "a.txt.tmp-" + dead + "-17", "a.txt.tmp-" + alive + "-99",
        "b.txt.tmp-" + dead + "-0", std::string("a.txt.tmp-x-0")}) {
    writeTextFileAtomically(dir / (name + ".seed"), "left");
    fs::rename(dir / (name + ".seed"), dir / name);
  }
  writeTextFileAtomically(dir / "a.txt", "new");
  EXPECT_EQ(readText(dir / "a.txt"), "new");
  // the dead run's temporaries of a.txt are gone; a live process's, another output's and names
  // that only look alike stay
  EXPECT_FALSE(fs::exists(dir / ("a.txt.tmp-" + dead + "-0")));
  EXPECT_FALSE(fs::exists(dir / ("a.txt.tmp-" + dead + "-17")));
  EXPECT_TRUE(fs::exists(dir / ("a.txt.tmp-" + alive + "-99")));
  EXPECT_TRUE(fs::exists(dir / ("b.txt.tmp-" + dead + "-0")));
  EXPECT_TRUE(fs::exists(dir / "a.txt.tmp-x-0"));
}

TEST(AtomicFile, FifoIsRefusedAndKept) {
  const fs::path dir = testing::freshTempDir();
  const fs::path fifo = dir / "pipe.jbi";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0) << std::strerror(errno);
  const std::string message = writeError(fifo);
  EXPECT_TRUE(contains(message, "output path is a FIFO (named pipe), not a regular file: '" +
                                    fifo.string() + "'; choose a regular file path"));
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(fifo)));
  EXPECT_EQ(entryCount(dir), 1u);
}

TEST(AtomicFile, CharacterDeviceIsRefusedAndKept) {
  if (::geteuid() != 0) GTEST_SKIP() << "mknod of a character device needs root";
  const fs::path dir = testing::freshTempDir();
  const fs::path device = dir / "null";  // the numbers of /dev/null: harmless if ever written
  ASSERT_EQ(::mknod(device.c_str(), S_IFCHR | 0600, ::makedev(1, 3)), 0) << std::strerror(errno);
  EXPECT_TRUE(
      contains(writeError(device), "output path is a character device, not a regular file"));
  struct stat st {};
  ASSERT_EQ(::lstat(device.c_str(), &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode));
  EXPECT_EQ(st.st_rdev, ::makedev(1, 3));
  EXPECT_EQ(entryCount(dir), 1u);
}

TEST(AtomicFile, SocketAndFolderAreRefused) {
  const fs::path dir = testing::freshTempDir();
  const fs::path socketPath = dir / "s";
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  ASSERT_LT(socketPath.string().size(), sizeof(address.sun_path));
  std::strcpy(address.sun_path, socketPath.c_str());
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)), 0);
  EXPECT_TRUE(contains(writeError(socketPath), "output path is a socket, not a regular file"));
  EXPECT_TRUE(fs::is_socket(fs::symlink_status(socketPath)));
  ::close(fd);
  fs::create_directory(dir / "folder");
  EXPECT_TRUE(contains(writeError(dir / "folder"), "output path is a folder, not a regular file"));
}

TEST(AtomicFile, SymlinkToARegularFileIsWrittenThrough) {
  const fs::path dir = testing::freshTempDir();
  fs::create_directory(dir / "real");
  std::ofstream(dir / "real" / "target.txt") << "old";
  fs::create_symlink(fs::path("real") / "target.txt", dir / "link.txt");
  writeTextFileAtomically(dir / "link.txt", "new");
  EXPECT_TRUE(fs::is_symlink(dir / "link.txt"));
  EXPECT_EQ(readText(dir / "real" / "target.txt"), "new");
  EXPECT_EQ(entryCount(dir / "real"), 1u);
}

TEST(AtomicFile, SymlinkToAFifoOrToNothingIsRefused) {
  const fs::path dir = testing::freshTempDir();
  ASSERT_EQ(::mkfifo((dir / "pipe").c_str(), 0600), 0);
  fs::create_symlink(dir / "pipe", dir / "to_pipe");
  EXPECT_TRUE(contains(writeError(dir / "to_pipe"),
                       "output path is a symbolic link to a FIFO (named pipe): '"));
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(dir / "pipe")));
  fs::create_symlink(dir / "nowhere", dir / "dangling");
  EXPECT_TRUE(
      contains(writeError(dir / "dangling"), "output path is a symbolic link to a missing file"));
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir / "dangling")));
  EXPECT_FALSE(fs::exists(dir / "nowhere"));
}

TEST(AtomicFile, EmptyPathOrOneNamingNoFileIsInvalidInput) {
  const fs::path dir = testing::freshTempDir();
  try {
    writeTextFileAtomically(fs::path(), "new");
    ADD_FAILURE() << "an empty path was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()),
              "output path is empty: ''; pass a file path such as 'PART.JBI'");
  }
  try {
    writeTextFileAtomically(dir / "missing" / "", "new");
    ADD_FAILURE() << "a path ending in a separator was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_TRUE(contains(e.what(), "output path names no file: '"));
    EXPECT_TRUE(contains(e.what(), "missing/PART.JBI'"));
  }
  EXPECT_EQ(entryCount(dir), 0u);
}

}  // namespace
}  // namespace curvedslicer
