// Subcommands of the tristereo program. Each returns the process exit code and
// throws cli::UsageError or tristereo::Error on bad input (main prints them).
#pragma once

namespace tristereo::cli {

int cmd_match(int argc, char** argv);
int cmd_verify(int argc, char** argv);
int cmd_synth(int argc, char** argv);
int cmd_eval(int argc, char** argv);
int cmd_info(int argc, char** argv);
int cmd_demo(int argc, char** argv);
int cmd_rectify(int argc, char** argv);

}  // namespace tristereo::cli
