// All of a command's outputs, or none of them.
//
// Each library writer is atomic for its own file (a temporary renamed into
// place), but a run with several outputs that fails at the fourth would leave
// three new files beside old ones. An OutputSet stages every output first:
//  1. each regular-file output is written by its writer to a temporary beside
//     its target (".NAME.tmp-PID-N.EXT": the same folder, so the rename cannot
//     cross file systems, and the same extension, which selects the format);
//     the writers flush and fsync it (io_detail::OutputFile);
//  2. an output whose target is a device or a FIFO (/dev/null, /dev/full, a
//     pipe) cannot be staged: it is written in place, after every file was
//     staged, so that a full device still leaves every file target untouched;
//  3. only when all of them succeeded are the temporaries renamed over their
//     targets. A target that existed is first hard-linked to a backup beside
//     it, so that a rename failing half-way (which no full disk can cause:
//     renames take no space) puts back every target already replaced.
// On any failure the temporaries and backups are removed, no target has
// changed, and the error (tristereo::Error, the writer's code) names the
// option and the target, not the temporary. A symbolic link at a target keeps
// pointing at the file it names, which is the one replaced.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace tristereo::cli {

class OutputSet {
 public:
  // `write(path)` writes the output to `path` (a temporary, or the target
  // itself for a device); `option` ("--disp") prefixes its errors.
  void add(const std::string& option, const std::string& target, std::function<void(const std::string&)> write);
  // Stages, then renames everything into place; throws on the first failure
  // after undoing everything. Runs once.
  void commit();

 private:
  struct Output {
    std::string option, target, final_path, temp;
    std::function<void(const std::string&)> write;
    bool device = false;
  };
  std::vector<Output> outputs_;
};

// The folder of a command's outputs (synth OUTDIR, demo OUTDIR): created,
// with its missing parents, if needed (kIoError naming it otherwise), and
// removed again, if it was created here, unless keep() is called once the
// outputs are in place: a failed run leaves no empty folder behind either.
class OutputFolder {
 public:
  explicit OutputFolder(const std::string& path);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;
  void keep() { created_.clear(); }

 private:
  std::vector<std::string> created_;  // innermost first
};

}  // namespace tristereo::cli
