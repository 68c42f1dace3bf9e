// io::OutputSet: a command's outputs appear as one set (or not at all), a second writer is
// refused, leftovers of killed runs are cleared, and a user's own files are never replaced.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "loopscan/io/errors.hpp"
#include "loopscan/io/output_set.hpp"
#include "support/io_fixture.hpp"

namespace loopscan {
namespace {

namespace fs = std::filesystem;
using io::OutputSet;
using test::error_of;
using test::has;

class OutputSetTest : public test::IoFixture {
 protected:
  std::string target() const { return (dir_ / "out").string(); }
  void put(const std::string& dir, const std::string& name, const std::string& text) const {
    fs::create_directories(fs::path(dir / fs::path(name)).parent_path());
    std::ofstream(fs::path(dir) / name) << text;
  }
  // Names in the parent directory other than the target: leftovers, locks.
  std::set<std::string> beside_target() const {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) {
      if (e.path().filename() != "out") names.insert(e.path().filename().string());
    }
    return names;
  }
  std::set<std::string> files_of(const std::string& d) const {
    std::set<std::string> names;
    for (const auto& e : fs::recursive_directory_iterator(d)) {
      names.insert(fs::relative(e.path(), d).string());
    }
    return names;
  }
};

TEST_F(OutputSetTest, CommitMakesTheWholeSetAppearAndReplacesTheOldOne) {
  {
    OutputSet set(target(), OutputSet::Kind::Directory, "run A");
    put(set.path(), "a.txt", "A");
    put(set.path(), "sub/b.txt", "A");
    EXPECT_FALSE(fs::exists(target()));  // nothing visible before the commit
    set.commit();
  }
  EXPECT_EQ(files_of(target()), (std::set<std::string>{".loopscan", "a.txt", "sub", "sub/b.txt"}));
  EXPECT_EQ(slurp(target() + "/.loopscan"), "run A\na.txt\nsub\nsub/b.txt\n");  // command, entries
  EXPECT_TRUE(beside_target().empty());  // no staging directory, no lock file
  {
    OutputSet set(target() + "/", OutputSet::Kind::Directory, "run B");  // trailing slash
    put(set.path(), "c.txt", "B");
    EXPECT_EQ(slurp(target() + "/a.txt"), "A");  // the old set stays whole until the commit
    set.commit();
  }
  EXPECT_EQ(files_of(target()), (std::set<std::string>{".loopscan", "c.txt"}));
  EXPECT_TRUE(beside_target().empty());
}

TEST_F(OutputSetTest, WithoutRenameExchangeTheTwoRenameSwapGivesTheSameResult) {
  { OutputSet(target(), OutputSet::Kind::Directory, "A").commit(); }
  ::setenv("LOOPSCAN_NO_RENAME_EXCHANGE", "1", 1);
  {
    OutputSet set(target(), OutputSet::Kind::Directory, "B");
    put(set.path(), "b.txt", "B");
    set.commit();
  }
  ::unsetenv("LOOPSCAN_NO_RENAME_EXCHANGE");
  EXPECT_EQ(files_of(target()), (std::set<std::string>{".loopscan", "b.txt"}));
  EXPECT_TRUE(beside_target().empty());
}

TEST_F(OutputSetTest, WithoutCommitTheOldSetStaysAndTheStagingGoes) {
  { OutputSet(target(), OutputSet::Kind::Directory, "old").commit(); }
  put(target(), "keep.txt", "old");
  {
    OutputSet set(target(), OutputSet::Kind::Directory, "new");
    put(set.path(), "keep.txt", "new");
  }  // e.g. an exception in the command
  EXPECT_EQ(slurp(target() + "/keep.txt"), "old");
  EXPECT_TRUE(beside_target().empty());
}

TEST_F(OutputSetTest, ASecondWriterIsRefusedUntilTheFirstIsDone) {
  auto first = std::make_unique<OutputSet>(target(), OutputSet::Kind::Directory);
  const std::string msg = error_of([&] { OutputSet second(target(), OutputSet::Kind::Directory); });
  EXPECT_TRUE(has(msg, "no other loopscan command writing it")) << msg;
  EXPECT_TRUE(has(msg, "pid " + std::to_string(::getpid()))) << msg;
  EXPECT_TRUE(fs::exists(first->path()));  // the refused writer left the first one alone
  first->commit();
  first.reset();
  OutputSet third(target(), OutputSet::Kind::Directory);  // free again
  third.commit();
}

TEST_F(OutputSetTest, UserFilesAreNeverReplaced) {
  put(target(), "thesis.tex", "months of work");
  const std::string msg = error_of([&] { OutputSet set(target(), OutputSet::Kind::Directory); });
  EXPECT_TRUE(has(msg, "no .loopscan marker")) << msg;
  EXPECT_EQ(slurp(target() + "/thesis.tex"), "months of work");
  EXPECT_TRUE(beside_target().empty());
  fs::remove_all(target());
  fs::create_directories(target());  // an empty directory may be replaced
  { OutputSet(target(), OutputSet::Kind::Directory).commit(); }
  EXPECT_TRUE(fs::exists(target() + "/.loopscan"));
  put(dir_.string(), "file.txt", "x");
  EXPECT_TRUE(
      has(error_of([&] { OutputSet((dir_ / "file.txt").string(), OutputSet::Kind::Directory); }),
          "a directory (it is a file)"));
  EXPECT_TRUE(
      has(error_of([&] { OutputSet(target(), OutputSet::Kind::File); }), "it is a directory"));
  EXPECT_TRUE(has(error_of([&] { OutputSet(".", OutputSet::Kind::Directory); }), "not '.'"));
}

TEST_F(OutputSetTest, LeftoversOfKilledRunsAreClearedAndAnInterruptedSwapRolledBack) {
  { OutputSet(target(), OutputSet::Kind::Directory, "old").commit(); }
  put((dir_ / ".out.staging.99999").string(), "half.txt", "partial");  // killed while writing
  put(dir_.string(), ".out.lock", "4242");                             // its lock (released)
  put(dir_.string(), ".other.staging.1", "not ours");                  // another target's
  put((dir_ / "out.tmp.2024").string(), "backup.txt", "a user's");     // not a leftover of ours
  { OutputSet(target(), OutputSet::Kind::Directory, "new").commit(); }
  EXPECT_EQ(beside_target(), (std::set<std::string>{".other.staging.1", "out.tmp.2024"}));
  EXPECT_EQ(slurp(target() + "/.loopscan"), "new\n");
  // A swap cut between its two renames (no RENAME_EXCHANGE): only `.out.old.<pid>` exists.
  fs::rename(target(), dir_ / ".out.old.777");
  { OutputSet set(target(), OutputSet::Kind::Directory, "newer"); }  // no commit
  EXPECT_EQ(slurp(target() + "/.loopscan"), "new\n");                // rolled back
}

TEST_F(OutputSetTest, FileTargetsHoldTheLockAndClearStaleTemporaries) {
  put(dir_.string(), "map.db.tmp.31337", "partial");
  {
    OutputSet set((dir_ / "map.db").string(), OutputSet::Kind::File);
    EXPECT_EQ(set.path(), (dir_ / "map.db").string());
    EXPECT_TRUE(
        has(error_of([&] { OutputSet again((dir_ / "map.db").string(), OutputSet::Kind::File); }),
            "no other loopscan command"));
    put(dir_.string(), "map.db", "written");
    set.commit();
  }
  EXPECT_EQ(beside_target(), (std::set<std::string>{"map.db"}));
}

TEST_F(OutputSetTest, ASymlinkedOutputIsFollowed) {
  const fs::path real = dir_ / "real";
  { OutputSet(real.string(), OutputSet::Kind::Directory).commit(); }
  fs::create_directory_symlink(real, dir_ / "link");
  {
    OutputSet set((dir_ / "link").string(), OutputSet::Kind::Directory);
    put(set.path(), "x.txt", "via link");
    set.commit();
  }
  EXPECT_TRUE(fs::is_symlink(dir_ / "link"));
  EXPECT_EQ(slurp((real / "x.txt").string()), "via link");
}

// Another command's output nested in a set (describe --out exp/sc inside simulate's exp), or
// files added by hand: replacing the set would delete them, so the command is refused.
TEST_F(OutputSetTest, EntriesTheSetDoesNotListAreNeverDeleted) {
  {
    OutputSet set(target(), OutputSet::Kind::Directory, "simulate");
    put(set.path(), "gt.txt", "1");
    set.commit();
  }
  { OutputSet(target() + "/sc", OutputSet::Kind::Directory, "describe").commit(); }
  const std::string msg = error_of([&] { OutputSet(target(), OutputSet::Kind::Directory); });
  EXPECT_TRUE(has(msg, "it also holds sc, sc/.loopscan")) << msg;
  EXPECT_TRUE(fs::exists(target() + "/sc/.loopscan"));
  fs::remove_all(target() + "/sc");
  // Written while the new set was being made: the swap is refused, the old set stays whole.
  OutputSet set(target(), OutputSet::Kind::Directory, "simulate again");
  put(target(), "notes.txt", "written meanwhile");
  EXPECT_TRUE(has(error_of([&] { set.commit(); }), "notes.txt"));
  EXPECT_EQ(slurp(target() + "/notes.txt"), "written meanwhile");
}

TEST_F(OutputSetTest, LinksAreFollowedEvenToTargetsNotCreatedYet) {
  fs::create_directory_symlink(dir_ / "later", dir_ / "dangling");  // `later` does not exist
  {
    OutputSet set((dir_ / "dangling").string(), OutputSet::Kind::Directory);
    put(set.path(), "x.txt", "1");
    set.commit();
  }
  EXPECT_TRUE(fs::is_symlink(dir_ / "dangling"));
  EXPECT_TRUE(fs::exists(dir_ / "later/x.txt"));
  // File targets too: the file the link names is replaced, the link stays.
  put(dir_.string(), "map.db", "old");
  fs::create_symlink("map.db", dir_ / "current.db");
  {
    OutputSet set((dir_ / "current.db").string(), OutputSet::Kind::File);
    EXPECT_EQ(set.path(), (dir_ / "map.db").string());
    set.commit();
  }
  EXPECT_TRUE(fs::is_symlink(dir_ / "current.db"));
}

TEST_F(OutputSetTest, FileTargetsMustBeFilesOfTheirKind) {
  EXPECT_TRUE(has(error_of([&] { OutputSet((dir_ / "map.db/").string(), OutputSet::Kind::File); }),
                  "not one ending in '/'"));
  put(dir_.string(), "notes.txt", "my notes");
  const auto is_db = [](const std::string& p) {
    return test::IoFixture::slurp(p).rfind("LOOPSCDB", 0) == 0;
  };
  const std::string msg =
      error_of([&] { OutputSet((dir_ / "notes.txt").string(), OutputSet::Kind::File, "", is_db); });
  EXPECT_TRUE(has(msg, "a file of the kind this command writes")) << msg;
  put(dir_.string(), "map.db", "LOOPSCDB...");
  OutputSet ok((dir_ / "map.db").string(), OutputSet::Kind::File, "", is_db);
  ok.commit();
}

}  // namespace
}  // namespace loopscan
