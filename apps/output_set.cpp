#include "apps/output_set.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "apps/option_errors.hpp"
#include "apps/output_paths.hpp"
#include "tristereo/status.hpp"

namespace tristereo::cli {

namespace {

std::string extension_of(const std::string& name) {
  const std::size_t dot = name.find_last_of('.');
  return dot == std::string::npos || dot == 0 ? "" : name.substr(dot);
}

// A hidden name beside `path` that no other process or output uses: the
// process id and a counter, as io_detail::OutputFile names its temporaries.
std::string beside(const std::string& path, const char* kind, bool keep_extension) {
  static std::atomic<unsigned> counter{0};
  const std::string name = name_of(path);
  return folder_of(path) + "/." + name + "." + kind + "-" + std::to_string(::getpid()) + "-" +
         std::to_string(counter.fetch_add(1)) + (keep_extension ? extension_of(name) : "");
}

// The writer's message names the temporary; the user gave the target.
std::string with_target(std::string message, const std::string& temp, const std::string& target) {
  for (std::size_t at = message.find(temp); at != std::string::npos; at = message.find(temp, at + target.size()))
    message.replace(at, temp.size(), target);
  return message;
}

}  // namespace

void OutputSet::add(const std::string& option, const std::string& target,
                    std::function<void(const std::string&)> write) {
  Output o;
  o.option = option;
  o.target = target;
  o.final_path = target;
  o.write = std::move(write);
  struct stat st {};
  if (::stat(target.c_str(), &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode)) {
    o.device = true;  // written in place, never replaced (file_util.hpp, OutputFile)
  } else {
    // A link is followed: the file it names is replaced, the link stays.
    struct stat lst {};
    char real[PATH_MAX];
    if (::lstat(target.c_str(), &lst) == 0 && S_ISLNK(lst.st_mode) && ::realpath(target.c_str(), real))
      o.final_path = real;
  }
  outputs_.push_back(std::move(o));
}

void OutputSet::commit() {
  std::vector<std::string> temps, backups;  // to remove on any exit
  struct Renamed {
    std::string final_path, backup;
    bool existed = false;  // and backup empty: no backup could be made
  };
  std::vector<Renamed> renamed;
  auto cleanup = [&] {
    for (const std::string& t : temps) ::unlink(t.c_str());
    for (const std::string& b : backups) ::unlink(b.c_str());
  };
  // Puts back every target already replaced (commit's step 3 failing).
  auto roll_back = [&] {
    for (auto it = renamed.rbegin(); it != renamed.rend(); ++it) {
      if (!it->backup.empty()) ::rename(it->backup.c_str(), it->final_path.c_str());
      else if (!it->existed) ::unlink(it->final_path.c_str());
    }
  };
  auto run = [&](Output& o, const std::string& path) {
    try {
      o.write(path);
    } catch (const Error& e) {
      const std::string m = with_target(without_function_prefix(e.what()), path, o.target);
      throw Error(e.code(), o.option + ": " + m);
    }
  };
  try {
    // 1. Files, to temporaries beside their targets.
    for (Output& o : outputs_) {
      if (o.device) continue;
      o.temp = beside(o.final_path, "tmp", true);
      temps.push_back(o.temp);
      run(o, o.temp);
    }
    // 2. Devices and FIFOs, in place, once every file is staged.
    for (Output& o : outputs_)
      if (o.device) run(o, o.target);
    // 3. Every file into place; a backup link of each existing target first.
    for (Output& o : outputs_) {
      if (o.device) continue;
      Renamed r{o.final_path, "", false};
      struct stat st {};
      r.existed = ::lstat(o.final_path.c_str(), &st) == 0;
      if (r.existed) {
        // A second name for the old file costs no space. A file system
        // without hard links (FAT) gets none: that target alone could then
        // not be put back if a later rename failed.
        const std::string backup = beside(o.final_path, "bak", false);
        if (::link(o.final_path.c_str(), backup.c_str()) == 0) {
          r.backup = backup;
          backups.push_back(backup);
        }
      }
      if (std::rename(o.temp.c_str(), o.final_path.c_str()) != 0)
        throw Error(ErrorCode::kIoError, o.option + ": cannot write '" + o.target + "': " + std::strerror(errno));
      renamed.push_back(r);
    }
  } catch (...) {
    roll_back();
    cleanup();
    throw;
  }
  cleanup();  // the backups; the temporaries are renamed already
  outputs_.clear();
}

OutputFolder::OutputFolder(const std::string& path) {
  // Each missing level, outermost last in created_, so that the destructor
  // removes the innermost first; rmdir never removes a folder holding files.
  std::string p = path;
  while (!p.empty() && p.back() == '/' && p.size() > 1) p.pop_back();
  std::vector<std::string> missing;
  for (std::string q = p; !q.empty() && q != "." && q != "/"; q = folder_of(q)) {
    struct stat st {};
    if (::stat(q.c_str(), &st) == 0) break;
    missing.push_back(q);
    if (q.find('/') == std::string::npos) break;
  }
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
    if (::mkdir(it->c_str(), 0777) != 0 && errno != EEXIST) {
      const int err = errno;
      for (const std::string& c : created_) ::rmdir(c.c_str());
      throw Error(ErrorCode::kIoError, "cannot create '" + path + "': " + std::strerror(err));
    }
    created_.insert(created_.begin(), *it);
  }
  struct stat st {};
  if (::stat(p.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) {
    for (const std::string& c : created_) ::rmdir(c.c_str());
    throw Error(ErrorCode::kIoError, "cannot create '" + path + "': " + std::strerror(ENOTDIR));
  }
}

OutputFolder::~OutputFolder() {
  for (const std::string& c : created_) ::rmdir(c.c_str());
}

}  // namespace tristereo::cli
