#include "io/formats/OutputFile.hpp"

#include <algorithm>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "text/NumberText.hpp"

namespace fs = std::filesystem;

namespace flexmb::io {

namespace {
std::string reason(int err, const char* fallback) { return err ? std::strerror(err) : fallback; }

// fsync the file so that a full disk shows up here (delayed allocation) and not after "wrote".
void syncFile(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0) throw std::runtime_error("cannot write '" + path + "': " + reason(errno, "cannot reopen it"));
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  if (rc != 0 && err != EINVAL && err != EROFS)  // EINVAL: special files that cannot sync
    throw std::runtime_error("cannot write '" + path + "': " + reason(err, "fsync failed"));
}
}  // namespace

std::string temporaryName(const std::string& path) { return path + ".part-" + std::to_string(::getpid()); }

void commitTemporary(const std::string& temp, const std::string& path, bool sync) {
  try {
    if (sync) syncFile(temp);
  } catch (...) {
    std::remove(temp.c_str());
    throw;
  }
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    std::remove(temp.c_str());
    throw std::runtime_error("cannot write '" + path + "': " + reason(err, "rename failed"));
  }
}

void writeThroughMemory(const std::string& path, const std::function<void(const std::string&)>& writer) {
  const int fd = ::memfd_create("flexmb-output", MFD_CLOEXEC);
  if (fd < 0) {
    writer(path);
    return;
  }
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  writer("/proc/self/fd/" + std::to_string(fd));
  // A file size limit (ulimit -f) applies to the memory file too, and the writer would not say.
  struct rlimit limit {};
  const off_t size = ::lseek(fd, 0, SEEK_END);
  if (::getrlimit(RLIMIT_FSIZE, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY &&
      static_cast<rlim_t>(size) >= limit.rlim_cur)
    throw std::runtime_error("cannot write '" + path + "': it reached the file size limit (ulimit -f)");
  if (::lseek(fd, 0, SEEK_SET) != 0)
    throw std::runtime_error("cannot write '" + path + "': " + reason(errno, "seek failed"));
  errno = 0;
  std::FILE* out = std::fopen(path.c_str(), "wb");
  if (!out) throw std::runtime_error("cannot write '" + path + "': " + reason(errno, "cannot create it"));
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0) {
      std::fclose(out);
      throw std::runtime_error("cannot write '" + path + "': " + reason(errno, "read failed"));
    }
    if (n == 0) break;
    errno = 0;
    if (std::fwrite(buffer, 1, static_cast<size_t>(n), out) != static_cast<size_t>(n)) {
      const int err = errno;
      std::fclose(out);
      throw std::runtime_error("cannot write '" + path + "': " + reason(err, "short write"));
    }
  }
  errno = 0;
  const bool bad = std::ferror(out) != 0;
  if (std::fclose(out) != 0 || bad)
    throw std::runtime_error("cannot write '" + path + "': " + reason(errno, "write failed"));
}

void checkMatFileComplete(const std::string& path) {
  std::error_code ec;
  const auto size = fs::file_size(path, ec);
  if (ec) throw std::runtime_error("cannot write '" + path + "': " + ec.message());
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw std::runtime_error("cannot write '" + path + "': cannot reopen it to check it");
  auto truncated = [&] {
    std::fclose(f);
    return std::runtime_error("cannot write '" + path + "': the file is incomplete (disk full or file size limit?)");
  };
  unsigned char header[128];
  if (size < 128 || std::fread(header, 1, 128, f) != 128) throw truncated();
  const bool swap = header[126] == 'M' && header[127] == 'I';
  std::uint64_t pos = 128;
  while (pos < size) {
    std::uint32_t tag[2];
    if (pos + 8 > size || std::fseek(f, static_cast<long>(pos), SEEK_SET) != 0 || std::fread(tag, 4, 2, f) != 2)
      throw truncated();
    if (swap)
      for (auto& w : tag) w = __builtin_bswap32(w);
    std::uint64_t n = tag[1];
    if (tag[0] >> 16)
      n = 0;  // small data element: the data lives in the tag
    else if (tag[0] != 15)
      n = (n + 7) / 8 * 8;  // miCOMPRESSED is not padded
    pos += 8 + n;
  }
  if (pos != size) throw truncated();
  std::fclose(f);
}

OutputFile::OutputFile(std::string path, bool sync) : path_(std::move(path)), temp_(temporaryName(path_)), sync_(sync) {
  out_.open(temp_, std::ios::binary);
  if (!out_) throw std::runtime_error("cannot write '" + path_ + "': " + reason(errno, "cannot create it"));
  out_.precision(17);
}

OutputFile::~OutputFile() {
  if (!done_) {
    out_.close();
    std::remove(temp_.c_str());
  }
}

void OutputFile::commit() {
  errno = 0;
  out_.flush();
  const bool bad = !out_;
  const int err = errno;
  out_.close();
  if (bad || out_.fail()) {
    std::remove(temp_.c_str());
    done_ = true;
    throw std::runtime_error("cannot write '" + path_ + "': " + reason(err, "write failed"));
  }
  done_ = true;
  commitTemporary(temp_, path_, sync_);
}

std::string OutputSet::resolvePrefix(const std::string& out, const std::string& modelFile, const std::string& suffix) {
  const std::string stem = fs::path(modelFile).stem().string() + suffix;
  if (out.empty()) return stem;
  std::error_code ec;
  if (out.back() == '/' || fs::is_directory(out, ec)) {
    std::string dir = out;
    while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
    return (fs::path(dir) / stem).string();
  }
  return out;
}

OutputSet::OutputSet(std::string prefix) : prefix_(std::move(prefix)) {}

OutputSet::~OutputSet() {
  for (const auto& f : files_) std::remove(f.second.c_str());  // what was not renamed
}

void OutputSet::checkWritable() const {
  fs::path dir = fs::path(prefix_).parent_path();
  if (dir.empty()) dir = ".";
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw std::runtime_error("cannot write results to '" + prefix_ + "*': the folder '" + dir.string() +
                             "' does not exist (create it first, or choose another --out)");
  const std::string probe = temporaryName(prefix_ + "_probe");
  {
    std::ofstream p(probe);
    p << "probe\n";
    p.flush();
    if (!p) {
      const int err = errno;
      std::remove(probe.c_str());
      throw std::runtime_error("cannot write results to '" + prefix_ +
                               "*': " + reason(err, "the folder is not writable") + " (choose another --out)");
    }
  }
  std::remove(probe.c_str());
  std::remove(manifestPath().c_str());  // an earlier run's files are no longer a complete set
}

std::string OutputSet::temporaryFor(const std::string& suffix) {
  files_.emplace_back(prefix_ + suffix, temporaryPrefix() + suffix);
  return files_.back().second;
}

std::string OutputSet::temporaryPath(const std::string& path) {
  files_.emplace_back(path, temporaryName(path));
  return files_.back().second;
}

void OutputSet::discardPending() {
  for (const auto& f : files_) std::remove(f.second.c_str());
  files_.clear();
}

bool OutputSet::attempt(const std::string& what, const std::function<void()>& step, std::ostream& err) {
  try {
    step();
    renameFiles();
    return true;
  } catch (const ProductFailed& e) {
    discardPending();
    setting("not written", what + ": " + e.what());
  } catch (const std::exception& e) {
    discardPending();
    setting("not written", what + ": " + e.what());
    err << "flexmb: " << what << " not written: " << e.what() << "; the other results are written\n";
  }
  return false;
}

void OutputSet::adopt(const std::string& temporary, const std::string& path) { files_.emplace_back(path, temporary); }

void OutputSet::setting(const std::string& name, double value) { setting(name, text::shortest(value)); }

std::vector<std::string> OutputSet::renameFiles() {
  // Every file that is whole is renamed even when another is not: one truncated .mat must not take
  // the complete files of the same run with it. The failures are reported together afterwards.
  std::string failed;
  for (const auto& [final, temp] : files_) {
    try {
      const std::string ext = fs::path(final).extension().string();
      if (ext == ".mat" || ext == ".sbd" || ext == ".sbm") {  // MAT v5 files (matio ignores a full disk)
        try {
          checkMatFileComplete(temp);
        } catch (const std::exception&) {
          std::remove(temp.c_str());
          throw;
        }
      }
      commitTemporary(temp, final, sync_);
      renamed_.push_back(final);
    } catch (const std::exception& e) {
      failed += (failed.empty() ? "" : "; ") + std::string(e.what());
    }
  }
  files_.clear();
  for (auto& r : removeStaleSpacarCompanions(renamed_)) removedStale_.push_back(std::move(r));
  if (!failed.empty()) throw std::runtime_error(failed);
  return renamed_;
}

std::vector<std::string> removeStaleSpacarCompanions(const std::vector<std::string>& written) {
  static const char* const kFamily[] = {".sbd", ".sbm", ".ltv"};
  std::vector<std::string> removed;
  for (const std::string& w : written) {
    const fs::path p(w);
    const std::string ext = p.extension().string();
    if (ext != ".sbd") continue;  // every SPACAR result set has its .sbd; its companions are optional
    for (const char* other : kFamily) {
      fs::path companion = p;
      companion.replace_extension(other);
      const std::string c = companion.string();
      if (std::find(written.begin(), written.end(), c) != written.end()) continue;
      std::error_code ec;
      if (fs::exists(companion, ec) && fs::remove(companion, ec)) removed.push_back(c);
    }
  }
  return removed;
}

std::string describeRemovedStale(const std::string& path) {
  return "removed " + path + ": an earlier run's file under this run's name (this run writes no " +
         fs::path(path).extension().string() + "; getfrsbf would have read another analysis from it)";
}

std::string OutputSet::writeManifest(const std::string& status) {
  // Files beside the manifest by their names, others by their path relative to it.
  fs::path dir = fs::path(manifestPath()).parent_path();
  if (dir.empty()) dir = ".";
  auto listed = [&](const std::string& p) {
    std::error_code ec;
    const fs::path rel = fs::proximate(p, dir, ec);
    std::string s = ec ? p : rel.string();
    if (fs::is_directory(p, ec) && (s.empty() || s.back() != '/')) s += "/";
    return s;
  };
  OutputFile m(manifestPath(), sync_);
  // A product of the run that could not be written (setting "not written") makes the set incomplete.
  bool missing = false;
  for (const auto& kv : settings_) missing = missing || kv.first == "not written";
  m << "flexmb run\nstatus: " << (missing ? "incomplete (see not written): " : "") << status << "\n";
  for (const auto& [name, value] : settings_) m << name << ": " << value << "\n";
  for (const auto& w : renamed_) m << "file: " << listed(w) << "\n";
  for (const auto& w : recorded_) m << "file: " << listed(w) << "\n";
  for (const auto& w : removedStale_) m << "removed: " << listed(w) << " (an earlier run's, not written by this one)\n";
  m.commit();
  return manifestPath();
}

std::vector<std::string> OutputSet::commit(const std::string& status) {
  std::vector<std::string> written = renameFiles();
  written.insert(written.end(), recorded_.begin(), recorded_.end());
  written.push_back(writeManifest(status));
  return written;
}

}  // namespace flexmb::io
