#include "Common/SafeOutput.h"

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <system_error>

#include "Common/Error.h"

namespace vs {

namespace fs = std::filesystem;

namespace {

std::string osReason(int errorNumber) {
  return errorNumber ? std::generic_category().message(errorNumber) : std::string("unknown reason");
}

std::string named(const std::string& role, const std::string& path) {
  return role.empty() ? path : role + " '" + path + "'";
}

// The temporary files a signal must remove. A slot is 0 free, 1 being filled, 2 live; the handler
// reads only live slots, with async-signal-safe calls (unlink, signal, raise).
constexpr int kSlots = 64;
constexpr size_t kSlotPath = 4096;
// Every member initialised, so that the array is constant-initialised (zero pages of the program's
// bss, touched only where a slot is used): with `path` left out, a start-up initialiser wrote each
// slot's state, 64 pages faulted in by every process before main.
struct TemporarySlot {
  std::atomic<int> state{0};
  char path[kSlotPath] = {};
};
TemporarySlot g_temporaries[kSlots];

extern "C" void removeTemporariesAndDie(int signalNumber) {
  for (TemporarySlot& slot : g_temporaries)
    if (slot.state.load() == 2) ::unlink(slot.path);
  std::signal(signalNumber, SIG_DFL);
  std::raise(signalNumber);
}

void installSignalHandlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (int signalNumber : {SIGINT, SIGTERM, SIGHUP}) {
      struct sigaction old {};
      if (::sigaction(signalNumber, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;  // nohup
      struct sigaction action {};
      action.sa_handler = removeTemporariesAndDie;
      sigemptyset(&action.sa_mask);
      ::sigaction(signalNumber, &action, nullptr);
    }
    // Past `ulimit -f` a write fails with EFBIG instead of killing the process: reported, cleaned up.
    std::signal(SIGXFSZ, SIG_IGN);
  });
}

int registerTemporary(const std::string& path) {
  if (path.size() >= kSlotPath) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (g_temporaries[i].state.compare_exchange_strong(expected, 1)) {
      std::memcpy(g_temporaries[i].path, path.c_str(), path.size() + 1);
      g_temporaries[i].state.store(2);
      return i;
    }
  }
  return -1;  // more than kSlots outputs at once: still removed on errors, not on signals
}

void unregisterTemporary(int slot) {
  if (slot >= 0) g_temporaries[slot].state.store(0);
}

}  // namespace

bool sameFile(const std::string& a, const std::string& b) {
  struct stat infoA {}, infoB {};
  if (::stat(a.c_str(), &infoA) == 0 && ::stat(b.c_str(), &infoB) == 0)
    return infoA.st_dev == infoB.st_dev && infoA.st_ino == infoB.st_ino;
  // Where either name cannot be made canonical (too long, a loop of links), compare the names as
  // written: two failures must not read as the same (empty) path.
  std::error_code ecA, ecB;
  const fs::path canonicalA = fs::weakly_canonical(fs::absolute(a, ecA), ecA);
  const fs::path canonicalB = fs::weakly_canonical(fs::absolute(b, ecB), ecB);
  if (ecA || ecB) return fs::path(a).lexically_normal() == fs::path(b).lexically_normal();
  return canonicalA == canonicalB;
}

void SafeOutputFile::checkPath(const std::string& path, const std::vector<std::string>& inputPaths,
                               const std::string& role) {
  if (path.empty()) throw InputError((role.empty() ? std::string("output") : role) + ": file name is empty");
  for (const std::string& input : inputPaths)
    if (!input.empty() && sameFile(path, input))
      throw InputError(named(role, path) + ": output file is the same file as input '" + input +
                       "'; refusing to overwrite an input");
  // Names the file system would refuse at the end of the run (rename) are refused now.
  const std::string fileName = fs::path(path).filename().string();
  if (fileName.size() > 255)
    throw InputError(named(role, path.substr(0, 60) + "...") + ": the file name is " + std::to_string(fileName.size()) +
                     " bytes long; at most 255 expected");
  if (path.size() >= 4096)
    throw InputError(named(role, path.substr(0, 60) + "...") + ": the path is " + std::to_string(path.size()) +
                     " bytes long; at most 4095 expected");
  std::error_code ec;
  const fs::path absolutePath = fs::absolute(path, ec);
  if (ec) throw InputError(named(role, path) + ": cannot resolve the output path: " + ec.message());
  const fs::path folder = absolutePath.parent_path();
  if (!fs::exists(folder, ec))
    throw InputError(named(role, path) + ": output folder '" + folder.string() + "' does not exist");
  if (!fs::is_directory(folder, ec))
    throw InputError(named(role, path) + ": output folder '" + folder.string() + "' is not a folder");
  if (fs::is_directory(absolutePath, ec)) throw InputError(named(role, path) + ": output path is a folder, not a file");
}

SafeOutputFile::SafeOutputFile(std::string path, const std::vector<std::string>& inputPaths, const std::string& role)
    : path_(std::move(path)), role_(role) {
  checkPath(path_, inputPaths, role_);
  installSignalHandlers();
  std::error_code ec;
  struct stat existing {};
  const bool exists = ::stat(path_.c_str(), &existing) == 0;
  if (exists && !S_ISREG(existing.st_mode)) {
    // A device or FIFO: written in place (rename would replace the device node itself).
    fd_ = ::open(path_.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd_ < 0) {
      const int error = errno;
      throw InputError(named(role_, path_) + ": cannot open the output: " + osReason(error));
    }
    return;
  }
  // A symbolic link keeps pointing where it did: the file it names is replaced.
  fs::path target = fs::absolute(path_, ec);
  if (fs::is_symlink(fs::symlink_status(target, ec))) {
    const fs::path resolved = fs::weakly_canonical(target, ec);
    if (!ec) target = resolved;
  }
  target_ = target.string();
  const fs::path folder = target.parent_path();
  const std::string stem = target.filename().string();
  // The signals that remove temporaries wait while one is created and registered: a signal between
  // the two would leave a file the handler does not know.
  sigset_t cleanupSignals, previousMask;
  sigemptyset(&cleanupSignals);
  for (int signalNumber : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&cleanupSignals, signalNumber);
  pthread_sigmask(SIG_BLOCK, &cleanupSignals, &previousMask);
  struct MaskRestorer {
    const sigset_t& mask;
    ~MaskRestorer() { pthread_sigmask(SIG_SETMASK, &mask, nullptr); }
  } restorer{previousMask};
  for (int attempt = 0; attempt < 100 && fd_ < 0; ++attempt) {
    // ".NAME.vs-PID-N", shortened when the name is long (a file name has at most 255 bytes).
    const std::string tag = ".vs-" + std::to_string(::getpid()) + "-" + std::to_string(attempt);
    const std::string name = stem.size() + tag.size() + 1 <= 255 ? "." + stem + tag : tag.substr(1) + ".tmp";
    temporaryPath_ = (folder / name).string();
    fd_ = ::open(temporaryPath_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd_ < 0 && errno != EEXIST) {
      const int error = errno;
      temporaryPath_.clear();
      throw InputError(named(role_, path_) + ": cannot create the output file in folder '" + folder.string() +
                       "': " + osReason(error));
    }
  }
  if (fd_ < 0) {
    temporaryPath_.clear();
    throw InputError(named(role_, path_) + ": cannot create a temporary file in folder '" + folder.string() + "'");
  }
  slot_ = registerTemporary(temporaryPath_);
  // The new file keeps the permissions of the one it replaces.
  struct stat previous {};
  if (::stat(target_.c_str(), &previous) == 0 && S_ISREG(previous.st_mode))
    (void)::fchmod(fd_, previous.st_mode & 07777);
}

SafeOutputFile::~SafeOutputFile() {
  if (!committed_) discard();
}

void SafeOutputFile::write(const void* data, size_t bytes) {
  if (committed_ || fd_ < 0) throw InputError(named(role_, path_) + ": the output is already closed");
  const char* at = static_cast<const char*>(data);
  size_t left = bytes;
  while (left > 0) {
    const ssize_t written = ::write(fd_, at, left);
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) {
      const int error = written < 0 ? errno : ENOSPC;
      lastError_ = error;
      throw InputError(named(role_, path_) + ": writing failed after " + std::to_string(bytesWritten_ + (bytes - left)) +
                       " bytes: " + osReason(error));
    }
    at += written;
    left -= size_t(written);
  }
  bytesWritten_ += bytes;
}

void SafeOutputFile::commit() {
  if (committed_) return;
  if (fd_ < 0) throw InputError(named(role_, path_) + ": the output was discarded");
  const int closed = ::close(fd_);
  const int closeError = errno;
  fd_ = -1;
  if (closed != 0) {
    discard();
    throw InputError(named(role_, path_) + ": writing failed: " + osReason(closeError));
  }
  if (!temporaryPath_.empty() && ::rename(temporaryPath_.c_str(), target_.c_str()) != 0) {
    const int error = errno;
    discard();
    throw InputError(named(role_, path_) + ": cannot move the finished output into place: " + osReason(error));
  }
  unregisterTemporary(slot_);
  slot_ = -1;
  committed_ = true;
}

void SafeOutputFile::discard() {
  if (fd_ >= 0) {
    ::close(fd_);
    fd_ = -1;
  }
  unregisterTemporary(slot_);
  slot_ = -1;
  if (!temporaryPath_.empty() && !committed_) ::unlink(temporaryPath_.c_str());
  temporaryPath_.clear();
}

}  // namespace vs
