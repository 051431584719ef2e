#pragma once
// Outputs that never damage a file (doc/formats-yuv.md, "Safe outputs"):
//   - every output is written to a temporary file in its destination folder and renamed onto its
//     name by commit(), when the run has ended well; until then the previous file, if any, is
//     untouched, and a run that fails or is refused leaves it exactly as it was;
//   - an output that is not committed (an error, an exception) has its temporary file removed; so
//     has every open temporary file on SIGINT, SIGTERM and SIGHUP (the signal then ends the process
//     as it would have). SIGXFSZ (file size limit) is ignored so that the write fails with EFBIG
//     and is reported; only SIGKILL (or a power cut) can leave a temporary file ".NAME.vs-XXXX";
//   - two runs writing one output at once each write their own temporary file: the later rename
//     wins and the file is always one run's whole output, never a mix;
//   - an output that exists and is not a regular file (/dev/null, /dev/full, a FIFO) is written
//     directly: there is nothing to rename onto a device;
//   - an output that is one of the run's inputs (config, camera file, sequences), by any spelling,
//     symbolic or hard link, is refused before anything is created.
// Write errors (a full disk, /dev/full, EFBIG) throw InputError naming the file and the OS reason.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace vs {

// True when `a` and `b` name the same file: the same device and inode when both exist (links and
// other spellings), else the same weakly canonical absolute path.
bool sameFile(const std::string& a, const std::string& b);

class SafeOutputFile {
public:
  // Checks `path` (checkPath), then creates the temporary file. Throws InputError naming `role` (a
  // key such as "ReportFile", or empty) and `path`.
  explicit SafeOutputFile(std::string path, const std::vector<std::string>& inputPaths = {},
                          const std::string& role = "");
  SafeOutputFile(const SafeOutputFile&) = delete;
  SafeOutputFile& operator=(const SafeOutputFile&) = delete;
  // Not committed: the temporary file is removed, the destination keeps what it held.
  ~SafeOutputFile();

  // Throws InputError when `path` could not be an output: empty, the same file as one of
  // `inputPaths`, a folder, or in a folder that does not exist. Creates nothing.
  static void checkPath(const std::string& path, const std::vector<std::string>& inputPaths = {},
                        const std::string& role = "");

  const std::string& path() const { return path_; }
  // Where the bytes go until commit(): the temporary file, or path() for a device or FIFO.
  const std::string& writingPath() const { return temporaryPath_.empty() ? path_ : temporaryPath_; }
  uint64_t bytesWritten() const { return bytesWritten_; }
  // The OS error of the last failed write (0: none), for callers that word their own message.
  int lastError() const { return lastError_; }

  // Writes every byte (retrying short writes); throws InputError with the OS reason on failure.
  void write(const void* data, size_t bytes);
  void write(const std::string& text) { write(text.data(), text.size()); }
  // Closes the file and renames it onto path(); throws InputError (and removes the temporary file)
  // when closing or renaming fails. Idempotent.
  void commit();
  // Removes the temporary file now. Idempotent.
  void discard();

private:
  std::string path_;           // the destination, as given
  std::string target_;         // the destination with symbolic links resolved: what rename() replaces
  std::string temporaryPath_;  // empty in direct mode
  std::string role_;
  int fd_ = -1;
  int slot_ = -1;  // in the signal handler's list of temporary files
  uint64_t bytesWritten_ = 0;
  int lastError_ = 0;
  bool committed_ = false;
};

}  // namespace vs
