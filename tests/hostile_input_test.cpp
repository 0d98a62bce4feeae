// Input from outside that is wrong in ways a parser does not see: paths that are not readable
// files, frames whose numbers overflow, a reference that is all zero, a file that claims a size
// it does not occupy. Each is refused with exit status 2 and a message naming the file.
#include <sys/stat.h>

#include <fstream>

#include "cli_fixture.h"
#include "eitbench/bench/io/child_read.h"
#include "eitbench/bench/methods/evaluate.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace {

void write_csv(const std::string& file, const std::vector<std::vector<double>>& rows) {
  std::ofstream out(file);
  out.precision(17);
  for (const auto& row : rows) {
    for (std::size_t k = 0; k < row.size(); ++k) out << (k ? "," : "") << row[k];
    out << "\n";
  }
}

std::vector<double> ramp(double scale) {
  std::vector<double> v(208);
  for (int k = 0; k < 208; ++k) v[k] = scale * (1 + 0.01 * k);
  return v;
}

// A missing path reads "no such file" in every command, whatever the format it would have been;
// a folder where a file belongs, or a FIFO, is named as such.
TEST_F(Cli, MissingInputsReadNoSuchFile) {
  const std::string missing = path("absent");
  for (const std::string& args :
       {"info " + missing + ".h5", "reconstruct --data " + missing + ".h5 --out " + path("o.h5"),
        "reconstruct --data " + missing + ".csv --out " + path("o.h5"),
        "import --in " + missing + ".npz --out " + path("o.h5"),
        "forward --mesh " + missing + ".msh --conductivity 1 --out " + path("o.csv"),
        "compare " + missing + ".json " + missing + "2.json",
        "calibrate --reference " + missing + ".mat --out " + path("s.json")}) {
    const Result r = run(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(missing), std::string::npos) << args << "\n" << r.output;
    EXPECT_NE(r.output.find("no such file"), std::string::npos) << args << "\n" << r.output;
  }
  const Result folder = run("reconstruct --data " + path("") + " --out " + path("o.h5"));
  EXPECT_EQ(folder.exit_code, 2);
  EXPECT_NE(folder.output.find("is a folder, not a file"), std::string::npos) << folder.output;
  ASSERT_EQ(::mkfifo(path("fifo.csv").c_str(), 0600), 0);
  const Result fifo = run("reconstruct --data " + path("fifo.csv") + " --out " + path("o.h5"));
  EXPECT_EQ(fifo.exit_code, 2);
  EXPECT_NE(fifo.output.find("not a regular file"), std::string::npos) << fifo.output;
  EXPECT_FALSE(fs::exists(path("o.h5")));
}

// Frames of 1e300 used to give NaN images (noser, tv, greit) or zeros (gn) and exit 0.
TEST_F(Cli, FramesWhoseSquaresOverflowAreRefused) {
  write_csv(path("big.csv"), {ramp(1), ramp(1e300)});
  for (const char* method : {"noser", "gn", "tv", "greit"}) {
    const Result r = run(std::string("reconstruct --method ") + method + " --data " +
                         path("big.csv") + " --png 0 --out " + path("o.h5"));
    EXPECT_EQ(r.exit_code, 2) << method << "\n" << r.output;
    EXPECT_NE(r.output.find("frame 1"), std::string::npos) << method << "\n" << r.output;
    EXPECT_NE(r.output.find("1e+300"), std::string::npos) << method << "\n" << r.output;
    EXPECT_FALSE(fs::exists(path("o.h5"))) << method;
  }
}

// A zero reference is refused; frames equal to the reference are counted in a warning.
TEST_F(Cli, ImportRefusesAZeroReferenceAndCountsUnchangedFrames) {
  write_csv(path("frames.csv"), {ramp(1), ramp(1), ramp(1.5)});
  write_csv(path("zero.csv"), {std::vector<double>(208, 0.0)});
  write_csv(path("empty.csv"), {ramp(1)});
  const Result zero = run("import --in " + path("frames.csv") + " --reference " + path("zero.csv") +
                          " --out " + path("d.h5"));
  EXPECT_EQ(zero.exit_code, 2) << zero.output;
  EXPECT_NE(zero.output.find("zero.csv"), std::string::npos) << zero.output;
  EXPECT_NE(zero.output.find("all zero"), std::string::npos) << zero.output;
  EXPECT_FALSE(fs::exists(path("d.h5")));
  const Result same = run("import --in " + path("frames.csv") + " --reference " +
                          path("empty.csv") + " --out " + path("d.h5"));
  EXPECT_EQ(same.exit_code, 0) << same.output;
  EXPECT_NE(same.output.find("warning: 2 of 3 frames equal the reference"), std::string::npos)
      << same.output;
}

// A method whose image is not finite is an error naming the method, the frame and its values,
// for every frame (not only the timed ones).
class NanAfter final : public Reconstructor {
 public:
  explicit NanAfter(int good) : good_(good) {}
  std::string name() const override { return "nan-after"; }
  std::string settings() const override { return ""; }
  Eigen::VectorXd reconstruct(const Eigen::VectorXd& frame) const override {
    return Eigen::VectorXd::Constant(16, frame[0] < good_ ? 0.0 : NAN);
  }

 private:
  int good_;
};

TEST(Evaluate, RefusesImagesThatAreNotFinite) {
  SampleMatrix frames(40, 4);
  for (int i = 0; i < 40; ++i) frames.row(i).setConstant(i);
  EvaluationOptions o;
  o.timed_frames = 2;
  o.source = "measured.csv";
  EXPECT_NO_THROW(evaluate(NanAfter(100), frames, SampleMatrix(), PixelGrid(4, 1.0), o));
  try {
    evaluate(NanAfter(37), frames, SampleMatrix(), PixelGrid(4, 1.0), o);
    FAIL() << "a NaN image passed";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "measured.csv");
    EXPECT_EQ(e.field(), "frame 37");
    EXPECT_NE(std::string(e.what()).find("nan-after"), std::string::npos) << e.what();
  }
}

// --out onto an input, whatever the spelling, is refused and the input is left as it was.
TEST_F(Cli, OutputOntoAnInputIsRefused) {
  write_csv(path("fr.csv"), {ramp(1), ramp(1.5)});
  const std::string before = file_text(path("fr.csv"));
  ASSERT_EQ(::link(path("fr.csv").c_str(), path("hard.csv").c_str()), 0);
  for (const std::string& out :
       {path("fr.csv"), path("hard.csv"), (dir_ / "." / "fr.csv").string()}) {
    const Result r = run("augment --in " + path("fr.csv") + " --element rot:1 --out " + out);
    EXPECT_EQ(r.exit_code, 2) << out << "\n" << r.output;
    EXPECT_NE(r.output.find("is the same file as the input"), std::string::npos) << r.output;
  }
  ASSERT_EQ(run("import --in " + path("fr.csv") + " --out " + path("d.h5")).exit_code, 0);
  const std::string data = file_text(path("d.h5"));
  const Result r = run("reconstruct --data " + path("d.h5") + " --png 0 --out " +
                       (dir_ / "." / "d.h5").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("is the same file as the input"), std::string::npos) << r.output;
  EXPECT_EQ(file_text(path("fr.csv")), before);
  EXPECT_EQ(file_text(path("d.h5")), data);
}

// Only regular files are written: a FIFO stays a FIFO; a symbolic link stays a link and the file
// it points to is replaced; a link to nothing is refused.
TEST_F(Cli, OutputsAreRegularFilesAndLinksAreFollowed) {
  write_csv(path("fr.csv"), {ramp(1), ramp(1.5)});
  ASSERT_EQ(::mkfifo(path("fifo.csv").c_str(), 0600), 0);
  const Result fifo =
      run("augment --in " + path("fr.csv") + " --element rot:1 --out " + path("fifo.csv"));
  EXPECT_EQ(fifo.exit_code, 2) << fifo.output;
  EXPECT_NE(fifo.output.find("a FIFO, a device or a socket"), std::string::npos) << fifo.output;
  EXPECT_EQ(fs::status(path("fifo.csv")).type(), fs::file_type::fifo);

  { std::ofstream(path("target.csv")) << "old\n"; }
  fs::create_symlink(path("target.csv"), path("link.csv"));
  const Result link =
      run("augment --in " + path("fr.csv") + " --element rot:1 --out " + path("link.csv"));
  ASSERT_EQ(link.exit_code, 0) << link.output;
  EXPECT_TRUE(fs::is_symlink(path("link.csv")));
  EXPECT_NE(file_text(path("target.csv")), "old\n");
  ASSERT_EQ(run("augment --in " + path("fr.csv") + " --element rot:1 --out " + path("plain.csv"))
                .exit_code,
            0);
  EXPECT_EQ(file_text(path("target.csv")), file_text(path("plain.csv")));

  fs::create_symlink(path("nowhere.csv"), path("dangling.csv"));
  const Result dangling =
      run("augment --in " + path("fr.csv") + " --element rot:1 --out " + path("dangling.csv"));
  EXPECT_EQ(dangling.exit_code, 2) << dangling.output;
  EXPECT_NE(dangling.output.find("symbolic link to nothing"), std::string::npos);
  EXPECT_FALSE(fs::exists(path("nowhere.csv")));
}

// A sparse file claiming 64 GB buys its child reader no more time than the file it really is.
TEST_F(Cli, ChildReadLimitIgnoresTheApparentSize) {
  const std::string sparse = path("sparse.h5");
  { std::ofstream(sparse) << "x"; }
  fs::resize_file(sparse, 64ull << 30);
  const double small = detail::child_read_limit(EITBENCH_CLI);  // a real file of some MB
  EXPECT_LT(detail::child_read_limit(sparse), small + 1);
  EXPECT_LT(detail::child_read_limit(sparse), 200);
}

}  // namespace
}  // namespace eitbench
