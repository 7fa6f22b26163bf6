// Checking a command's output paths before it computes anything.
//
// Every output option is checked up front, so a typo in the last of several
// outputs costs nothing and leaves no earlier output written:
//  - the extension is one the option writes (UsageError naming the accepted
//    ones: the format follows the extension, never silently another format);
//  - the path is not one of the command's inputs, nor another output of the
//    same command (UsageError; compared after resolving symbolic links and
//    "..", and by device and inode when the file exists);
//  - its folder exists and is writable, and the path is not a folder
//    (tristereo::Error kIoError with the reason).
#pragma once

#include <string>
#include <vector>

#include "apps/cli_args.hpp"

namespace tristereo::cli {

struct OutputOption {
  const char* option;                   // without the dashes: "mesh"
  std::vector<const char*> extensions;  // lower case with the dot: {".ply"}
};

struct InputPath {
  std::string label;  // how the user named it: "LEFT", "RIGHT", "--calib"
  std::string path;
};

void check_output_paths(const Args& args, const std::vector<OutputOption>& outputs,
                        const std::vector<InputPath>& inputs);

// True when both paths name the same file (existing or to be created).
bool same_file(const std::string& a, const std::string& b);

// The folder a path names a file in ("." for a bare name, "/" at the root),
// and the file's name in it.
std::string folder_of(const std::string& path);
std::string name_of(const std::string& path);

}  // namespace tristereo::cli
