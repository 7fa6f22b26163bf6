#include "support/data.hpp"

#include <cstdlib>
#include <fstream>

namespace tristereo::test {

std::string data_root() {
  // The environment may point elsewhere (data kept outside the checkout's
  // parent, or a test of this very rule); else the folder the build was
  // configured with.
  const char* env = std::getenv("TRISTEREO_DATA_DIR");
  return env != nullptr && *env != '\0' ? env : TRISTEREO_DATA_DIR;
}

std::string data_set_dir(const std::string& set) { return data_root() + "/" + set; }

bool data_set_available(const std::string& set) {
  return std::ifstream(data_set_dir(set) + "/datasets.tsv").good();
}

bool missing_data_allowed() {
  const char* allow = std::getenv("TRISTEREO_ALLOW_MISSING_DATA");
  return allow != nullptr && std::string(allow) == "1";
}

}  // namespace tristereo::test
