#pragma once
// Checked, atomic result files. A result is written under a temporary name beside its final name
// and renamed into place only when every byte of it was written, so a kill, a full disk or a
// missing folder never leaves a half file under the final name, and a failed write is an error,
// never "wrote ...".
//
//   * OutputFile: one text file (a stream); commit() checks the stream, flushes to disk, renames.
//   * OutputSet: the file set of one run. resolve() turns --out into a prefix (a folder, "dir/" or
//     an existing directory, gets the model's name inside it); checkWritable() probes the folder
//     BEFORE the analysis; temporaryFor() hands out temporary names that any writer (CSV, matio)
//     can fill; commit() renames them all and then writes <prefix>_run.txt, the manifest that lists
//     the run's settings and files. A file set is complete iff its manifest exists: a new run
//     removes the old manifest first, so files of an earlier run never look complete after a kill.
//     Files that cannot be written under a temporary name (a picture series that names its own
//     files) are written between renameFiles() and writeManifest() and listed with record().
#include <fstream>
#include <functional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace flexmb::io {

// Thrown by a product step (OutputSet::attempt) that has already said why it failed.
struct ProductFailed : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class OutputFile {
 public:
  // sync = false: rename without fsync (see OutputSet::setSync). Throws std::runtime_error when the
  // temporary cannot be opened.
  explicit OutputFile(std::string path, bool sync = true);
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  ~OutputFile();  // removes the temporary when not committed
  template <class T>
  OutputFile& operator<<(const T& v) {
    out_ << v;
    return *this;
  }
  void commit();  // throws std::runtime_error naming the path and the reason; then nothing is left
  const std::string& path() const { return path_; }

 private:
  std::string path_, temp_;
  std::ofstream out_;
  bool done_ = false;
  bool sync_ = true;
};

// Temporary name of path: "<path>.part-<pid>" (same folder, so rename() is atomic).
std::string temporaryName(const std::string& path);
// fsync (unless sync is false) + rename temp to path; throws std::runtime_error (and removes temp)
// on failure.
void commitTemporary(const std::string& temp, const std::string& path, bool sync = true);
// Runs writer(p) on a path p in memory (a memfd), then copies the bytes to path with checked
// writes: for writers that do not report failed writes (matio ignores a full disk). Falls back to
// writer(path) where memfd is unavailable.
void writeThroughMemory(const std::string& path, const std::function<void(const std::string&)>& writer);
// A MATLAB v5 file whose data elements all end inside the file (a full disk truncates silently
// under matio); throws std::runtime_error naming the path.
void checkMatFileComplete(const std::string& path);

// A SPACAR result set is <base>.sbd with optional <base>.sbm and <base>.ltv beside it. For each
// .sbd among written, removes the companions that exist but are not among written (files of an
// earlier run of another analysis under the same name); returns their paths.
std::vector<std::string> removeStaleSpacarCompanions(const std::vector<std::string>& written);
// "removed <path>: an earlier run's file under this run's name (...)" for the screen.
std::string describeRemovedStale(const std::string& path);

class OutputSet {
 public:
  // --out as given (may be empty, a prefix, "dir/" or an existing directory) and the model file:
  // empty -> <model stem><suffix>; a folder -> <folder>/<model stem><suffix>; else out itself.
  static std::string resolvePrefix(const std::string& out, const std::string& modelFile,
                                   const std::string& suffix = "");

  explicit OutputSet(std::string prefix);
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;
  ~OutputSet();  // removes the temporaries not renamed

  const std::string& prefix() const { return prefix_; }
  // Throws std::runtime_error when the folder is missing or not writable (probes with a file);
  // removes the manifest of an earlier run with the same prefix.
  void checkWritable() const;
  // Registers the final path prefix + suffix and returns the temporary to write instead,
  // temporaryPrefix() + suffix (so a writer that appends suffixes to a prefix can fill several).
  std::string temporaryFor(const std::string& suffix);
  std::string temporaryPrefix() const { return temporaryName(prefix_); }
  // Registers a final path anywhere (--svg file.svg, <model>.sbd beside a CSV) and returns its
  // temporary, temporaryName(path).
  std::string temporaryPath(const std::string& path);
  // Registers a temporary that a writer already filled (e.g. under temporaryPrefix()) and its final path.
  void adopt(const std::string& temporary, const std::string& path);
  // Records a setting for the manifest ("reltol", "1e-3"); numbers in their shortest exact form.
  void setting(const std::string& name, const std::string& value) { settings_.emplace_back(name, value); }
  void setting(const std::string& name, double value);
  // Renames every temporary (a .mat is checked first). Returns the final paths. Throws on failure.
  // Then removes the SPACAR companions (.sbm, .ltv) an earlier run left beside a .sbd this run
  // wrote (removedStale()): getfrsbf reads them as one set.
  std::vector<std::string> renameFiles();
  const std::vector<std::string>& removedStale() const { return removedStale_; }
  // Drops the temporaries registered since the last renameFiles() (a step that failed half-way),
  // removing what of them exists; the files renamed before stay.
  void discardPending();
  // One product of a finished analysis (SPACAR's files, a picture, the echo) made by step and renamed
  // into place on its own. A failure is said on err ("flexmb: <what> not written: reason; the other
  // results are written"; not for ProductFailed, which said it already) and in the manifest ("not
  // written: ..."), its temporaries are dropped and the files renamed before it stand: a finished
  // run is never discarded by a step after it. Returns false on failure.
  bool attempt(const std::string& what, const std::function<void()>& step, std::ostream& err);
  // Lists a file (or folder) written under its final name after renameFiles().
  void record(const std::string& path) { recorded_.push_back(path); }
  // Writes the manifest with the status line ("complete" or why the run stopped) and every file
  // renamed or recorded; returns the manifest's path. Throws on failure.
  std::string writeManifest(const std::string& status);
  // renameFiles() and writeManifest(): the final paths, the manifest last.
  std::vector<std::string> commit(const std::string& status);
  std::string manifestPath() const { return prefix_ + "_run.txt"; }
  // false: commit renames without fsync. For many small file sets that can be made again (the
  // variants of a design study: four fsyncs cost more than a variant's analysis and queue the
  // workers on the disk's journal). Failed writes are still errors where the file system reports
  // them on write or close (ext4 reserves delayed-allocation blocks on write, NFS reports on close);
  // given up is that the bytes reach the disk before the manifest does, across a power failure:
  // a reader of such a set checks the files itself.
  void setSync(bool sync) { sync_ = sync; }

 private:
  std::string prefix_;
  std::vector<std::pair<std::string, std::string>> files_;  // final, temporary
  std::vector<std::pair<std::string, std::string>> settings_;
  std::vector<std::string> renamed_, recorded_, removedStale_;
  bool sync_ = true;
};

}  // namespace flexmb::io
