#include "apps/output_paths.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>

#include "tristereo/status.hpp"

namespace tristereo::cli {

namespace {

std::string lower_extension(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// The absolute path a file would have, links in its folder resolved; the path
// itself if the folder cannot be resolved (then it is reported missing anyway).
std::string resolved(const std::string& path) {
  char buf[PATH_MAX];
  if (::realpath(path.c_str(), buf)) return buf;
  if (::realpath(folder_of(path).c_str(), buf)) return std::string(buf) + "/" + name_of(path);
  return path;
}

}  // namespace

bool same_file(const std::string& a, const std::string& b) {
  struct stat sa {}, sb {};
  if (::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0)
    return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
  return resolved(a) == resolved(b);
}

void check_output_paths(const Args& args, const std::vector<OutputOption>& outputs,
                        const std::vector<InputPath>& inputs) {
  std::vector<std::pair<std::string, std::string>> seen;  // (--option, path)
  for (const OutputOption& out : outputs) {
    if (!args.has(out.option)) continue;
    const std::string opt = std::string("--") + out.option;
    const std::string path = args.get(out.option, "");
    if (path.empty()) throw UsageError(opt + " needs a file name");
    const std::string ext = lower_extension(path);
    bool known = false;
    std::string accepted;
    for (const char* e : out.extensions) {
      known = known || ext == e;
      accepted += (accepted.empty() ? "" : ", ") + std::string(e);
    }
    if (!known)
      throw UsageError(opt + " " + path + ": " +
                       (ext.empty() ? std::string("no extension") : "extension '" + ext + "' is not written") +
                       "; the file must end in " + accepted + " (the format follows the extension)");
    for (const InputPath& in : inputs) {
      if (!in.path.empty() && same_file(path, in.path))
        throw UsageError(opt + " " + path + " is the " + in.label +
                         " input; refusing to overwrite an input (choose another output name)");
    }
    for (const auto& [other_opt, other_path] : seen) {
      if (same_file(path, other_path))
        throw UsageError(opt + " " + path + " is also the " + other_opt +
                         " output; give each output its own file");
    }
    seen.emplace_back(opt, path);

    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode))
      throw Error(ErrorCode::kIoError, opt + " " + path + " is a folder; give a file name");
    const std::string dir = folder_of(path);
    if (::stat(dir.c_str(), &st) != 0) {
      throw Error(ErrorCode::kIoError, opt + " " + path + ": folder '" + dir + "': " +
                                           std::strerror(errno) + " (create it first)");
    }
    if (!S_ISDIR(st.st_mode))
      throw Error(ErrorCode::kIoError, opt + " " + path + ": '" + dir + "' is not a folder");
    if (::access(dir.c_str(), W_OK) != 0)
      throw Error(ErrorCode::kIoError, opt + " " + path + ": cannot write into folder '" + dir +
                                           "': " + std::strerror(errno));
  }
}

std::string folder_of(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

std::string name_of(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

}  // namespace tristereo::cli
