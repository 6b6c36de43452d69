// Output files and resource limits of every command (docs/cli.md#conventions-of-every-command,
// `--max-memory`), issue 17 groups 6 and 7: all outputs of a command are committed together or
// not at all, links and modes survive, signals leave no temporary; estimates over --max-memory,
// inputs that are not regular files and inputs over the limit are refused with exit 2.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "helpers.h"

namespace cover {
namespace {

namespace fs = std::filesystem;
using test::run_cover;

std::string q(const fs::path& p) { return "'" + p.string() + "'"; }

/// Runs `cover ARGS` on one thread with the address space capped at 2 GiB and the time at 20 s:
/// a command that would read or allocate without bound fails fast instead of exhausting the
/// machine. The checked build keeps only the time cap: AddressSanitizer reserves terabytes of
/// shadow address space at start, which no address-space cap allows.
test::RunResult run_capped(const std::string& args) {
#ifdef COVER_SANITIZED
  return run_cover(args + " --threads 1", "", "timeout 20 ");
#else
  return run_cover(args + " --threads 1", "", "ulimit -v 2097152; timeout 20 ");
#endif
}

constexpr char kBox[] = R"({"box": {"min": [0, 0, 0], "max": [1, 1, 1]}})";

/// The names in `dir` that look like a temporary output (FILE.tmp-PID-K).
std::vector<std::string> temporaries(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().filename().string().find(".tmp-") != std::string::npos)
      out.push_back(entry.path().filename().string());
  return out;
}

/// The one stderr line of a refused command, which must exit 2.
void expect_refused(const test::RunResult& r, const std::string& needle) {
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(r.err.rfind("cover: error: ", 0), 0u) << r.err;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
  EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
}

class Outputs : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::temp_dir("outputs");
    box_ = dir_ / "box.json";
    test::write_file(box_, kBox);
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// Runs `cover FIRST` to create `kept`, then `cover AGAIN` (which would write other contents
  /// there): that run must fail (exit 2) and leave `kept` byte for byte and no temporary.
  void expect_kept(const std::string& first, const std::string& again, const fs::path& kept) {
    ASSERT_EQ(run_cover(first).status, 0) << first;
    const std::string before = test::read_file(kept);
    ASSERT_FALSE(before.empty());
    const auto r = run_cover(again);
    EXPECT_EQ(r.status, 2) << again << ": " << r.err;
    EXPECT_TRUE(test::read_file(kept) == before) << again << ": " << kept << " changed";
    EXPECT_TRUE(temporaries(dir_).empty()) << again;
  }

  fs::path dir_, box_;
};

TEST_F(Outputs, FailedSecondaryOutputKeepsPrimary) {
  const std::string missing = q(dir_ / "missing" / "x");  // a folder that does not exist
  const std::string render = "render " + q(box_) + " -o " + q(dir_ / "keep.png");
  expect_kept(render + " --size 32x24", render + " --size 40x30 --depth /proc/d.png",
              dir_ / "keep.png");
  expect_kept(render + " --size 32x24", render + " --size 40x30 --ids " + missing + ".png",
              dir_ / "keep.png");
  const std::string voxelize = "voxelize " + q(box_) + " -o " + q(dir_ / "v.npy");
  expect_kept(voxelize + " --res 8", voxelize + " --res 9 --surface " + missing + ".obj",
              dir_ / "v.npy");
  const std::string clip = "clip " + q(box_) + " -o " + q(dir_ / "a.off");
  expect_kept(clip + " --plane 0,0,1,0.5", clip + " --plane 0,0,1,0.25 --below " + missing + ".off",
              dir_ / "a.off");
}

TEST_F(Outputs, RawKeptWhenSidecarCannotBeWritten) {
  // The sidecar's rename fails after the data file's: the old v.raw must come back.
  const fs::path raw = dir_ / "v.raw", sidecar = dir_ / "v.raw.json";
  ASSERT_EQ(run_cover("voxelize " + q(box_) + " --res 8 -o " + q(raw)).status, 0);
  const std::string before = test::read_file(raw);
  fs::remove(sidecar);
  fs::create_directory(sidecar);
  test::write_file(sidecar / "x", "a folder where the sidecar should go");
  const auto r = run_cover("voxelize " + q(box_) + " --res 9 -o " + q(raw));
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("v.raw.json"), std::string::npos) << r.err;
  ASSERT_TRUE(fs::is_regular_file(raw));
  EXPECT_TRUE(test::read_file(raw) == before) << "v.raw changed";
  EXPECT_TRUE(temporaries(dir_).empty());
}

TEST_F(Outputs, SymlinkAndModeKept) {
  const fs::path real = dir_ / "real", link = dir_ / "link.off", file = real / "m.off";
  fs::create_directory(real);
  ASSERT_EQ(run_cover("evaluate " + q(box_) + " -o " + q(file)).status, 0);
  // A new file gets the usual 0666 & ~umask.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  struct stat info {};
  ASSERT_EQ(::stat(file.c_str(), &info), 0);
  EXPECT_EQ(info.st_mode & 07777, 0666 & ~mask);
  ASSERT_EQ(::chmod(file.c_str(), 0640), 0);
  fs::create_symlink("real/m.off", link);
  const std::string before = test::read_file(file);
  test::write_file(dir_ / "big.json", R"({"box": {"min": [0, 0, 0], "max": [2, 2, 2]}})");
  ASSERT_EQ(run_cover("evaluate " + q(dir_ / "big.json") + " -o " + q(link)).status, 0);
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(fs::read_symlink(link), "real/m.off");
  EXPECT_NE(test::read_file(file), before);  // written through the link
  ASSERT_EQ(::stat(file.c_str(), &info), 0);
  EXPECT_EQ(info.st_mode & 07777, 0640u);
  EXPECT_TRUE(temporaries(dir_).empty());
  EXPECT_TRUE(temporaries(real).empty());
}

/// Starts `cover ARGS` with stdout and stderr discarded and SIGINT / SIGTERM / SIGHUP at their
/// defaults (the test runner may ignore or block some).
pid_t start_cover(const std::vector<std::string>& args) {
  std::vector<char*> argv{const_cast<char*>(COVER_BIN)};
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid != 0) return pid;
  for (const int s : {SIGINT, SIGTERM, SIGHUP}) ::signal(s, SIG_DFL);
  sigset_t none;
  sigemptyset(&none);
  ::sigprocmask(SIG_SETMASK, &none, nullptr);
  const int null = ::open("/dev/null", O_WRONLY);
  ::dup2(null, STDOUT_FILENO);
  ::dup2(null, STDERR_FILENO);
  ::execv(COVER_BIN, argv.data());
  ::_exit(127);
}

TEST_F(Outputs, SignalRemovesTemporary) {
  // A 1 GiB .npy: the signal arrives while its temporary is being written.
  const fs::path out = dir_ / "x.npy";
  for (const int s : {SIGTERM, SIGINT, SIGHUP}) {
    const pid_t pid = start_cover({"voxelize", box_.string(), "--res", "1024", "-o", out.string()});
    ASSERT_GT(pid, 0);
    int status = 0;
    bool exited = false;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (temporaries(dir_).empty() && std::chrono::steady_clock::now() < deadline) {
      if ((exited = ::waitpid(pid, &status, WNOHANG) == pid)) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ASSERT_FALSE(exited) << "voxelize ended before its temporary appeared";
    ASSERT_FALSE(temporaries(dir_).empty()) << "no temporary within 20 s";
    ::kill(pid, s);
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == s) << "signal " << s;
    EXPECT_TRUE(temporaries(dir_).empty()) << "signal " << s << ": " << temporaries(dir_)[0];
    EXPECT_FALSE(fs::exists(out));
  }
}

/// The names in `dir` that Cover's signal thread or a folder swap could leave (".tmp-" or
/// ".gone").
std::vector<std::string> leftovers(const fs::path& dir) {
  std::vector<std::string> out = temporaries(dir);
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().filename().string().find(".gone") != std::string::npos)
      out.push_back(entry.path().filename().string());
  return out;
}

/// The file names in `dir`, sorted.
std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& entry : fs::directory_iterator(dir)) out.push_back(entry.path().filename());
  std::sort(out.begin(), out.end());
  return out;
}

/// pieces.json's file names plus "pieces.json", sorted: what a pieces folder must hold exactly.
std::vector<std::string> listed_in(const fs::path& dir) {
  const nlohmann::json index = nlohmann::json::parse(test::read_file(dir / "pieces.json"));
  std::vector<std::string> out{"pieces.json"};
  for (const auto& p : index["pieces"]) out.push_back(p["file"].get<std::string>());
  std::sort(out.begin(), out.end());
  return out;
}

TEST_F(Outputs, SignalDuringZarrWriteRemovesTheTemporaryFolder) {
  // A .zarr store is a folder of chunk files written by several threads: SIGINT, SIGTERM or
  // SIGHUP while chunks are being written removes the whole temporary folder.
  const fs::path out = dir_ / "x.zarr";
  const std::string elephant = test::cgal_mesh("elephant.off").string();
  for (const int s : {SIGTERM, SIGINT, SIGHUP}) {
    const pid_t pid = start_cover({"voxelize", elephant, "--res", "4096", "--chunk", "64",
                                   "--threads", "2", "-o", out.string()});
    ASSERT_GT(pid, 0);
    int status = 0;
    bool exited = false, writing = false;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (!writing && std::chrono::steady_clock::now() < deadline) {
      if ((exited = ::waitpid(pid, &status, WNOHANG) == pid)) break;
      for (const std::string& t : temporaries(dir_)) {  // chunk files beside .zarray, .zattrs
        std::error_code ignored;
        const auto n =
            std::distance(fs::directory_iterator(dir_ / t, ignored), fs::directory_iterator());
        writing = writing || n > 2;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ASSERT_FALSE(exited) << "voxelize ended before its chunks appeared";
    ASSERT_TRUE(writing) << "no chunk within 30 s";
    ::kill(pid, s);
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == s) << "signal " << s;
    EXPECT_TRUE(leftovers(dir_).empty()) << "signal " << s << ": " << leftovers(dir_)[0];
    EXPECT_FALSE(fs::exists(out));
  }
}

TEST_F(Outputs, ZarrThroughASymlinkFillsTheFolderItNames) {
  const fs::path real = dir_ / "real.zarr", link = dir_ / "link.zarr";
  fs::create_directory(real);
  fs::create_directory_symlink("real.zarr", link);
  ASSERT_EQ(run_cover("voxelize " + q(box_) + " --res 8 -o " + q(link)).status, 0);
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(fs::read_symlink(link), "real.zarr");
  EXPECT_TRUE(fs::is_regular_file(real / ".zarray"));
  EXPECT_TRUE(leftovers(dir_).empty());
}

TEST_F(Outputs, PiecesFolderKeepsNoFileOfAnEarlierRun) {
  // --pieces DIR and decompose -o DIR: the second run's folder holds exactly its own files.
  const fs::path pieces = dir_ / "p";
  test::write_file(dir_ / "l.json", R"({"difference": [
      {"box": {"min": [0, 0, 0], "max": [2, 2, 2]}},
      {"box": {"min": [1, 1, 1], "max": [3, 3, 3]}}]})");
  const std::string cells = " -o " + q(dir_ / "g.off") + " --cells 2 --pieces " + q(pieces);
  ASSERT_EQ(run_cover("evaluate " + q(dir_ / "l.json") + cells + " --bounds 0,0,0,2").status, 0);
  ASSERT_EQ(listed_in(pieces).size(), 8u);  // 7 pieces
  ASSERT_EQ(run_cover("evaluate " + q(box_) + cells + " --bounds 0,0,0,2").status, 0);
  EXPECT_EQ(names_in(pieces), listed_in(pieces));
  EXPECT_EQ(listed_in(pieces).size(), 2u);  // the unit box is cell (0, 0, 0)
  EXPECT_TRUE(leftovers(dir_).empty());
  // decompose -o the same folder (a pieces folder Cover wrote) replaces it too.
  ASSERT_EQ(run_cover("decompose " + q(box_) + " -o " + q(pieces)).status, 0);
  EXPECT_EQ(names_in(pieces), (std::vector<std::string>{"piece_0000.off", "pieces.json"}));
  EXPECT_TRUE(leftovers(dir_).empty());
}

TEST_F(Outputs, PiecesFolderOfOtherFilesIsRefused) {
  // A folder Cover did not write is never replaced: refused (exit 2) before any work, its
  // files untouched. An empty folder is used.
  const fs::path mine = dir_ / "mine";
  fs::create_directory(mine);
  test::write_file(mine / "notes.txt", "keep");
  const std::string g = " -o " + q(dir_ / "g.off") + " --cells 2 --pieces ";
  for (const std::string& c :
       {"evaluate " + q(box_) + g + q(mine), "decompose " + q(box_) + " -o " + q(mine)}) {
    expect_refused(run_cover(c),
                   "mine: exists and is not a pieces folder written by Cover (it "
                   "holds 'notes.txt'); remove it or name another folder");
    EXPECT_EQ(names_in(mine), std::vector<std::string>{"notes.txt"});
    EXPECT_EQ(test::read_file(mine / "notes.txt"), "keep");
  }
  test::write_file(dir_ / "file", "x");
  expect_refused(run_cover("decompose " + q(box_) + " -o " + q(dir_ / "file")),
                 "file: exists and is not a folder");
  fs::create_directory(dir_ / "empty");
  ASSERT_EQ(run_cover("decompose " + q(box_) + " -o " + q(dir_ / "empty/")).status, 0);
  EXPECT_EQ(names_in(dir_ / "empty"), listed_in(dir_ / "empty"));
  EXPECT_TRUE(leftovers(dir_).empty());
}

TEST_F(Outputs, ConcurrentRunsIntoOnePiecesFolderDoNotMix) {
  // Two runs writing the same folder at once: it ends as one run's output, whole, and neither
  // run refuses the folder for the other's entries vanishing while it checks them.
  const fs::path pieces = dir_ / "p";
  test::write_file(dir_ / "l.json", R"({"difference": [
      {"box": {"min": [0, 0, 0], "max": [2, 2, 2]}},
      {"box": {"min": [1, 1, 1], "max": [3, 3, 3]}}]})");
  for (int round = 0; round < 12; ++round) {
    std::vector<pid_t> pids;
    for (const fs::path& in : {dir_ / "l.json", box_})
      pids.push_back(start_cover({"evaluate", in.string(), "-o",
                                  (dir_ / (in.stem().string() + ".off")).string(), "--cells", "2",
                                  "--bounds", "0,0,0,2", "--pieces", pieces.string()}));
    for (const pid_t pid : pids) {
      int status = 0;
      ASSERT_EQ(::waitpid(pid, &status, 0), pid);
      EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    }
    EXPECT_EQ(names_in(pieces), listed_in(pieces)) << "round " << round;
    EXPECT_TRUE(leftovers(dir_).empty());
  }
}

TEST_F(Outputs, PiecesFolderThroughASymlinkFillsTheFolderItNames) {
  const fs::path real = dir_ / "real", link = dir_ / "link";
  fs::create_directory(real);
  fs::create_directory_symlink("real", link);
  ASSERT_EQ(run_cover("decompose " + q(box_) + " -o " + q(link)).status, 0);
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(names_in(real), (std::vector<std::string>{"piece_0000.off", "pieces.json"}));
  EXPECT_TRUE(leftovers(dir_).empty());
}

class Limits : public Outputs {};

TEST_F(Limits, InfoOfDevZeroRefused) {
  const fs::path zero = dir_ / "zero.off";
  fs::create_symlink("/dev/zero", zero);
  expect_refused(run_capped("info " + q(zero)), "zero.off: not a regular file");
  // A FIFO is refused without waiting for a writer, a folder before reading it.
  const fs::path fifo = dir_ / "fifo.off";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  expect_refused(run_capped("info " + q(fifo)), "fifo.off: not a regular file");
  fs::create_directory(dir_ / "folder.json");
  expect_refused(run_cover("volume " + q(dir_ / "folder.json")), "folder.json: not a regular file");
  // A scene's mesh leaf and a points file are read the same way.
  test::write_file(dir_ / "s.json", R"({"mesh": "zero.off"})");
  expect_refused(run_capped("info " + q(dir_ / "s.json")), "not a regular file");
  expect_refused(run_capped("classify " + q(box_) + " --points /dev/zero"),
                 "/dev/zero: not a regular file");
}

TEST_F(Limits, InputOverMaxMemoryRefused) {
  // 2 MiB of blank lines: refused before reading, from a file or from stdin.
  const std::string blank(2 << 20, '\n');
  test::write_file(dir_ / "big.off", blank);
  expect_refused(run_cover("info " + q(dir_ / "big.off") + " --max-memory 1"),
                 "big.off: the file needs 2 MiB, over --max-memory 1 MiB");
  test::write_file(dir_ / "p.txt", blank);
  expect_refused(
      run_cover("classify " + q(box_) + " --points " + q(dir_ / "p.txt") + " --max-memory 1"),
      "p.txt: the file needs 2 MiB");
  expect_refused(run_cover("classify " + q(box_) + " --points - --max-memory 1", blank),
                 "<stdin>: the input needs");
  // 300 k points fit as text, not as points with their classes and output lines.
  std::string points;
  for (int i = 0; i < 300000; ++i) points += "0 0 0\n";
  test::write_file(dir_ / "p.txt", points);
  expect_refused(
      run_cover("classify " + q(box_) + " --points " + q(dir_ / "p.txt") + " --max-memory 2"),
      "p.txt: classifying 300000 lines of points needs");
}

TEST_F(Limits, OctreeDepth16Refused) {
  const auto start = std::chrono::steady_clock::now();
  const auto r = run_capped("octree " + q(box_) + " --depth 16 -o " + q(dir_ / "o.bt"));
  expect_refused(r, "--depth 16: the octree needs ");
  EXPECT_NE(r.err.find(" MiB, over --max-memory 4096 MiB"), std::string::npos) << r.err;
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
  EXPECT_FALSE(fs::exists(dir_ / "o.bt"));
  // The same limit allows what fits, and a smaller one refuses less.
  EXPECT_EQ(run_cover("octree " + q(box_) + " --depth 6 -o " + q(dir_ / "o.bt")).status, 0);
  expect_refused(
      run_cover("octree " + q(box_) + " --depth 9 -o " + q(dir_ / "o.bt") + " --max-memory 16"),
      "--depth 9: the octree needs ");
}

TEST_F(Limits, RenderHugeSizeRefused) {
  // 31 bytes a pixel (render_bytes), and with --samples S > 1 the S²-times larger sub-pixel
  // image besides.
  expect_refused(
      run_capped("render " + q(box_) + " --size 16384x16384 --samples 1 -o " + q(dir_ / "r.png")),
      "--size 16384x16384: the image needs 7936 MiB, over --max-memory 4096 MiB");
  expect_refused(run_capped("render " + q(box_) + " --size 16384x16384 -o " + q(dir_ / "r.png")),
                 "--size 16384x16384 with --samples 2: the image needs 39680 MiB, over "
                 "--max-memory 4096 MiB");
  expect_refused(
      run_cover("render " + q(box_) + " --size 256x256 --max-memory 1 -o " + q(dir_ / "r.png")),
      "the image needs 10 MiB, over --max-memory 1 MiB");
  EXPECT_FALSE(fs::exists(dir_ / "r.png"));
}

TEST_F(Limits, MaxMemoryOnEveryCommand) {
  const std::string in = q(box_), o = " -o " + q(dir_.string() + "/out");
  test::write_file(dir_ / "p.txt", "0.5 0.5 0.5\n");
  for (const std::string& c :
       {"info " + in, "volume " + in, "classify " + in + " --points " + q(dir_ / "p.txt"),
        "render " + in + " --size 16x16" + o + ".png", "voxelize " + in + " --res 8" + o + ".npy",
        "octree " + in + " --depth 3" + o + ".json",
        "clip " + in + " --plane 0,0,1,0.5" + o + ".off", "evaluate " + in + o + ".obj"}) {
    const auto r = run_cover(c + " --max-memory 64");
    EXPECT_EQ(r.status, 0) << c << ": " << r.err;
  }
  expect_refused(run_cover("volume " + in + " --max-memory 0"), "--max-memory");
}

}  // namespace
}  // namespace cover
