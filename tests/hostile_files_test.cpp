// Small files that asked for gigabytes. Each is crafted here, at test time (no large binaries in
// the repository), and run through the command that reads it under an address-space limit; the
// command must exit 2 within seconds, with a message naming the file, the field, the declared
// size or the rule, and a peak memory well under 1 GiB above the tool's own start-up size.
// The rule they are refused by is eitbench/jacobian/read_budget.h.
#include <H5Cpp.h>
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <chrono>
#include <cstring>
#include <fstream>
#include <sstream>

#include "cli_fixture.h"
#include "eitbench/bench/data/dataset_file.h"

namespace eitbench {
namespace {

struct Limited {
  int exit_code;
  std::string output;
  double seconds;
  double peak_mib;  // the command's peak resident memory, its children's included
};

// The address space a command may take (setrlimit RLIMIT_AS). eitbench starts in under 1 GiB of
// address space with LibTorch loaded; a reader that tried to hold gigabytes would die here.
constexpr double kAddressSpaceMiB = 1536;

class HostileFiles : public Cli {
 protected:
  // Runs eitbench with `args` (split at spaces) under RLIMIT_AS, as fork + exec, so that wait4
  // reports the command's own peak memory.
  Limited run_limited(const std::string& args, double address_space_mib) const {
    std::vector<std::string> words{EITBENCH_CLI};
    std::istringstream split(args);
    for (std::string w; split >> w;) words.push_back(w);
    const std::string log = path("limited_log.txt");
    const auto start = std::chrono::steady_clock::now();
    const pid_t pid = ::fork();
    if (pid == 0) {
      const rlimit limit{static_cast<rlim_t>(address_space_mib * 1048576),
                         static_cast<rlim_t>(address_space_mib * 1048576)};
      ::setrlimit(RLIMIT_AS, &limit);
      const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      ::dup2(fd, 1), ::dup2(fd, 2);
      std::vector<char*> argv;
      for (auto& w : words) argv.push_back(w.data());
      argv.push_back(nullptr);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
    int status = 0;
    rusage usage{};
    ::wait4(pid, &status, 0, &usage);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::ifstream in(log);
    std::stringstream text;
    text << in.rdbuf();
    return {WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status), text.str(), seconds,
            usage.ru_maxrss / 1024.0};
  }

  // Checks the refusal: exit 2, the file and `needle` in the message, seconds and memory bounded.
  void expect_refused(const std::string& args, const std::string& file, const std::string& needle) {
    const Limited version = run_limited("--version", kAddressSpaceMiB);
    ASSERT_EQ(version.exit_code, 0) << "eitbench does not start under the limit:\n"
                                    << version.output;
    const Limited r = run_limited(args, kAddressSpaceMiB);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(file), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(needle), std::string::npos) << r.output;
    EXPECT_LT(r.seconds, 20) << args;  // a hang guard: these take well under a second
    EXPECT_LT(r.peak_mib, version.peak_mib + 512)
        << args << ": peak " << r.peak_mib << " MiB, start-up " << version.peak_mib << " MiB";
    std::printf("  %s: exit %d in %.2f s, peak %.0f MiB (start-up %.0f MiB): %s", file.c_str(),
                r.exit_code, r.seconds, r.peak_mib, version.peak_mib, r.output.c_str());
  }
};

void put(std::string& b, std::uint64_t v, int bytes) {
  for (int k = 0; k < bytes; ++k) b += static_cast<char>((v >> (8 * k)) & 0xff);
}

std::string npy_header(const std::string& shape) {
  std::string dict = "{'descr': '<f8', 'fortran_order': False, 'shape': (" + shape + "), }";
  dict.append(118 - dict.size(), ' ');
  dict += '\n';
  std::string out = "\x93NUMPY\x01";
  out += '\0';
  put(out, dict.size(), 2);
  return out + dict;
}

// A zip archive of one member's bytes (stored or deflated) and `entries` directory entries that
// all point at it: the real archive has entries == 1.
std::string zip(const std::string& data, int method, std::uint32_t crc, std::uint64_t size,
                int entries) {
  std::string b;
  const std::string name = "frames.npy";
  put(b, 0x04034b50, 4), put(b, 20, 2), put(b, 0, 2), put(b, method, 2), put(b, 0, 4);
  put(b, crc, 4), put(b, data.size(), 4), put(b, size, 4), put(b, name.size(), 2), put(b, 0, 2);
  b += name + data;
  const std::size_t directory = b.size();
  for (int e = 0; e < entries; ++e) {
    const std::string entry = e == 0 ? name : "copy" + std::to_string(e) + ".npy";
    put(b, 0x02014b50, 4), put(b, 20, 2), put(b, 20, 2), put(b, 0, 2), put(b, method, 2);
    put(b, 0, 4), put(b, crc, 4), put(b, data.size(), 4), put(b, size, 4);
    put(b, entry.size(), 2), put(b, 0, 2), put(b, 0, 2), put(b, 0, 2), put(b, 0, 2), put(b, 0, 4);
    put(b, 0, 4);  // every entry's local header: the one member
    b += entry;
  }
  const std::size_t end = b.size();
  put(b, 0x06054b50, 4), put(b, 0, 4), put(b, entries, 2), put(b, entries, 2);
  put(b, end - directory, 4), put(b, directory, 4), put(b, 0, 2);
  return b;
}

void write_file(const std::string& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary) << bytes;
}

// 2,000 directory entries pointing at one stored 8 MB member: decoded 2,000 times, 16 GB.
TEST_F(HostileFiles, ZipEntriesSharingOneMember) {
  const std::string member = npy_header("4000, 250") + std::string(8'000'000, '\0');
  const std::uint32_t crc =
      crc32(0, reinterpret_cast<const Bytef*>(member.data()), static_cast<uInt>(member.size()));
  write_file(path("shared.npz"), zip(member, 0, crc, member.size(), 2000));
  expect_refused("import --in " + path("shared.npz") + " --out " + path("o.h5"), "shared.npz",
                 "overlaps the member");
  EXPECT_FALSE(fs::exists(path("o.h5")));
}

// Raw deflate of an .npy header and `zeros` zero bytes, built from one repeated flushed block so
// that gigabytes compress in milliseconds: after a full flush the coder starts afresh, and every
// block of zeros codes to the same bytes.
std::string deflate_zeros(const std::string& head, std::uint64_t zeros, std::uint32_t& crc) {
  constexpr std::size_t kBlock = 1 << 20;
  const std::string block(kBlock, '\0');
  z_stream z{};
  deflateInit2(&z, 9, Z_DEFLATED, -MAX_WBITS, 9, Z_DEFAULT_STRATEGY);
  std::string out;
  auto feed = [&](const std::string& in, int flush) {
    const std::size_t before = out.size();
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
    z.avail_in = static_cast<uInt>(in.size());
    do {
      char buffer[1 << 16];
      z.next_out = reinterpret_cast<Bytef*>(buffer);
      z.avail_out = sizeof buffer;
      deflate(&z, flush);
      out.append(buffer, sizeof buffer - z.avail_out);
    } while (z.avail_out == 0);
    return out.substr(before);
  };
  feed(head, Z_FULL_FLUSH);
  feed(block, Z_FULL_FLUSH);
  const std::string unit = feed(block, Z_FULL_FLUSH);
  EXPECT_EQ(feed(block, Z_FULL_FLUSH), unit);  // the repetition the shortcut relies on
  const std::uint64_t blocks = zeros / kBlock;
  for (std::uint64_t k = 3; k < blocks; ++k) out += unit;
  feed(std::string(zeros % kBlock, '\0'), Z_FINISH);
  deflateEnd(&z);
  const uLong block_crc = crc32(0, reinterpret_cast<const Bytef*>(block.data()), kBlock);
  crc = crc32(0, reinterpret_cast<const Bytef*>(head.data()), static_cast<uInt>(head.size()));
  for (std::uint64_t k = 0; k < blocks; ++k) crc = crc32_combine(crc, block_crc, kBlock);
  return out;
}

// One 2.9 MB member that inflates to 3 GB: refused from its declared size, before inflating; and
// when the directory understates it, inflation stops at the declared size.
TEST_F(HostileFiles, ZipMemberThatInflatesToGigabytes) {
  const std::uint64_t rows = 1'802'884, zeros = rows * 208 * 8;  // 3.0e9 bytes
  const std::string head = npy_header(std::to_string(rows) + ", 208");
  std::uint32_t crc = 0;
  const std::string data = deflate_zeros(head, zeros, crc);
  EXPECT_LT(data.size(), 3'500'000u);
  write_file(path("bomb.npz"), zip(data, 8, crc, head.size() + zeros, 1));
  // 3.0 GB from 2.9 MB is both past the cap and at deflate's own limit: either rule may speak.
  expect_refused("import --in " + path("bomb.npz") + " --out " + path("o.h5"), "bomb.npz",
                 "frames.npy: declares");
  write_file(path("lying.npz"), zip(data, 8, crc, 1 << 20, 1));
  expect_refused("import --in " + path("lying.npz") + " --out " + path("o.h5"), "lying.npz",
                 "decompresses to more than 1048576 bytes");
  EXPECT_FALSE(fs::exists(path("o.h5")));
}

// A 200 kB variable wrapped in 8,000 layers of miCOMPRESSED (stored, so building it is cheap):
// every layer was kept alive through the recursion, 2.4 GB.
TEST_F(HostileFiles, MatlabCompressionNestedEightThousandTimes) {
  std::string matrix;  // a 1 x 25,000 double "frames"
  auto element = [](std::uint32_t type, const std::string& data) {
    std::string e;
    put(e, type, 4), put(e, data.size(), 4);
    e += data;
    e.append((8 - data.size() % 8) % 8, '\0');
    return e;
  };
  std::string flags, dims, values(25'000 * 8, '\0');
  put(flags, 6, 4), put(flags, 0, 4);  // class double
  put(dims, 1, 4), put(dims, 25'000, 4);
  matrix =
      element(14, element(6, flags) + element(5, dims) + element(1, "frames") + element(9, values));
  std::string layer = matrix;
  for (int k = 0; k < 8000; ++k) {
    uLongf size = compressBound(static_cast<uLong>(layer.size()));
    std::string packed(size, '\0');
    compress2(reinterpret_cast<Bytef*>(packed.data()), &size,
              reinterpret_cast<const Bytef*>(layer.data()), static_cast<uLong>(layer.size()), 0);
    packed.resize(size);
    layer.clear();
    put(layer, 15, 4), put(layer, packed.size(), 4);
    layer += packed;
  }
  std::string header = "MATLAB 5.0 MAT-file, written by eitbench's hostile-file test";
  header.resize(116, ' ');
  put(header, 0, 8), put(header, 0x0100, 2);
  header += "IM";
  write_file(path("nested.mat"), header + layer);
  EXPECT_LT(fs::file_size(path("nested.mat")), 700'000u);
  expect_refused("info " + path("nested.mat"), "nested.mat", "MATLAB never nests them");
}

// One point entity in 50,000 physical groups and 50,000 point elements, each of which copied the
// tag list: 3.2 GB from 300 kB.
TEST_F(HostileFiles, GmshEntityWithFiftyThousandPhysicalTags) {
  std::ostringstream m;
  m << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n1 0 0 0\n1 0 0 0 50000";
  for (int k = 1; k <= 50000; ++k) m << ' ' << k;
  m << "\n$EndEntities\n$Nodes\n1 1 1 1\n0 1 0 1\n1\n0 0 0\n$EndNodes\n";
  m << "$Elements\n1 50000 1 50000\n0 1 15 50000\n";
  for (int k = 1; k <= 50000; ++k) m << k << " 1\n";
  m << "$EndElements\n";
  write_file(path("tags.msh"), m.str());
  expect_refused("forward --mesh " + path("tags.msh") + " --conductivity 1 --out " + path("o.csv"),
                 "tags.msh", "50000 physical groups, more than the 64");
}

// A valid 20-sample data set whose labels are re-declared as 20 x 4096 x 4096, chunked and never
// written (every value the fill value): 9.8 kB on disk, 1.3 GB declared.
TEST_F(HostileFiles, DatasetDeclaringLabelsNeverWritten) {
  Dataset d;
  d.reference = Eigen::VectorXd::Constant(208, 1.0);
  d.frames = SampleMatrix::Constant(20, 208, 1.0);
  d.differences = SampleMatrix::Constant(20, 104, 0.01);
  d.labels = SampleMatrix::Zero(20, 64 * 64);
  d.split.assign(20, Split::test);
  write_dataset(path("sparse.h5"), d);
  {
    H5::H5File file(path("sparse.h5"), H5F_ACC_RDWR);
    file.unlink("labels");
    const hsize_t dims[3] = {20, 4096, 4096}, chunk[3] = {1, 256, 256};
    H5::DSetCreatPropList props;
    props.setChunk(3, chunk);
    props.setDeflate(4);
    file.createDataSet("labels", H5::PredType::NATIVE_FLOAT, H5::DataSpace(3, dims), props);
    const int side = 4096;
    file.openAttribute("image_size").write(H5::PredType::NATIVE_INT, &side);
  }
  expect_refused("info " + path("sparse.h5"), "sparse.h5", "never written");
  expect_refused("reconstruct --data " + path("sparse.h5") + " --out " + path("o.h5"), "sparse.h5",
                 "labels");
}

// A MATLAB v7.3 file (HDF5 behind a 512-byte header) declaring 208 x 900,000 doubles, 1.5 GB,
// never written.
TEST_F(HostileFiles, MatlabV73DeclaringFramesNeverWritten) {
  {
    H5::FileCreatPropList create;
    create.setUserblock(512);
    H5::H5File file(path("sparse.mat"), H5F_ACC_TRUNC, create);
    const hsize_t dims[2] = {900'000, 208}, chunk[2] = {1024, 208};
    H5::DSetCreatPropList props;
    props.setChunk(2, chunk);
    H5::DataSet set =
        file.createDataSet("frames", H5::PredType::NATIVE_DOUBLE, H5::DataSpace(2, dims), props);
    const H5::StrType text(H5::PredType::C_S1, 6);
    set.createAttribute("MATLAB_class", text, H5::DataSpace(H5S_SCALAR)).write(text, "double");
  }
  std::fstream f(path("sparse.mat"), std::ios::in | std::ios::out | std::ios::binary);
  std::string header = "MATLAB 7.3 MAT-file, written by eitbench's hostile-file test";
  header.resize(116, ' ');
  f.write(header.data(), static_cast<std::streamsize>(header.size()));
  expect_refused("info " + path("sparse.mat"), "sparse.mat", "never written");
}

// 40 MB of one value a line: the width was checked only after the whole file was loaded (1.5 GB,
// 28 s). It is refused at the first line where a width cannot be a frame, and a file of frames as
// columns stops at the most lines a frame can have.
TEST_F(HostileFiles, CsvOfOneValueALine) {
  {
    std::ofstream out(path("column.csv"));
    const std::string line = "0.123456789\n";
    std::string chunk;
    for (int k = 0; k < 100'000; ++k) chunk += line;
    for (int k = 0; k < 34; ++k) out << chunk;  // 40.8 MB
  }
  expect_refused("augment --in " + path("column.csv") + " --element rot:1 --out " + path("o.csv"),
                 "column.csv", "line 1");
  expect_refused("import --in " + path("column.csv") + " --out " + path("o.h5"), "column.csv",
                 "line 257");
}

}  // namespace
}  // namespace eitbench
