// Reading untrusted HDF5 files in a child process
// (bench/io/include/eitbench/bench/io/child_read.h): what the child read comes back whole; its
// errors come back as the same InputError; its crash or hang becomes an InputError naming the file.
// The last test is the libhdf5 hang that fuzzing found.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <thread>

#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/io/child_read.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace {

using detail::read_in_child;

// Restores the child's time limit when a test that shortens it ends.
struct ShortLimit {
  explicit ShortLimit(double seconds) { detail::set_child_read_base_limit(seconds); }
  ~ShortLimit() { detail::set_child_read_base_limit(20); }
};

TEST(ChildRead, ReturnsWhatTheChildRead) {
  std::string sent(10'000'000, '\0');  // more than a pipe holds, with NULs in it
  for (std::size_t i = 0; i < sent.size(); ++i) sent[i] = static_cast<char>(i * 2654435761u >> 13);
  // The child prefixes its process id, 8 bytes, so that the test sees where the read ran.
  const std::string got = read_in_child("file.h5", [&] {
    const std::int64_t pid = ::getpid();
    return std::string(reinterpret_cast<const char*>(&pid), sizeof pid) + sent;
  });
  ASSERT_EQ(got.size(), 8 + sent.size());
  std::int64_t pid = 0;
  std::memcpy(&pid, got.data(), sizeof pid);
  EXPECT_NE(pid, ::getpid()) << "read in this process, not a child";
  EXPECT_TRUE(got.compare(8, std::string::npos, sent) == 0);
}

TEST(ChildRead, RethrowsTheChildsInputError) {
  try {
    read_in_child("file.h5", []() -> std::string {
      throw InputError("file.h5", "electrodes", "must be a single value");
    });
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "file.h5");
    EXPECT_EQ(e.field(), "electrodes");
    EXPECT_EQ(e.message(), "must be a single value");
  }
}

TEST(ChildRead, OtherExceptionsBecomeInputErrorsNamingTheFile) {
  try {
    read_in_child("file.h5", []() -> std::string { throw std::bad_alloc(); });
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "file.h5");
    EXPECT_NE(e.message().find("bad_alloc"), std::string::npos) << e.what();
  }
}

TEST(ChildRead, ACrashBecomesAnInputErrorNamingTheFile) {
  try {
    read_in_child("file.h5", []() -> std::string {
      std::signal(SIGSEGV, SIG_DFL);  // past any handler a sanitizer installed
      std::raise(SIGSEGV);
      return "";
    });
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "file.h5");
    EXPECT_NE(e.message().find("crashed"), std::string::npos) << e.what();
    EXPECT_NE(e.message().find("signal 11"), std::string::npos) << e.what();
  }
}

TEST(ChildRead, AHangIsKilledAtTheLimit) {
  const ShortLimit limit(1);
  const auto start = std::chrono::steady_clock::now();
  try {
    read_in_child("file.h5", []() -> std::string {
      for (;;) std::this_thread::sleep_for(std::chrono::seconds(1));
    });
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "file.h5");
    EXPECT_NE(e.message().find("did not finish"), std::string::npos) << e.what();
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(30));
}

TEST(ChildRead, ALibhdf5HangOnACorruptDataSetIsReportedNotSuffered) {
  // A mutant of a valid data set on which Debian 12's libhdf5 loops for ever while it reads a
  // variable-length string attribute (found by FuzzSmoke.dataset).
  const std::string file = std::string(EITBENCH_BAD_INPUTS) + "/../data/bad_hdf5_heap_loop.h5";
  const ShortLimit limit(2);
  try {
    read_dataset(file);
    FAIL() << "read a corrupt file";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), file);
    EXPECT_NE(e.message().find("did not finish"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace eitbench
