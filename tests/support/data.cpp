#include "support/data.hpp"

#include <cstdlib>
#include <fstream>

namespace tristereo::test {

std::string data_root() { return TRISTEREO_DATA_DIR; }

std::string data_set_dir(const std::string& set) { return data_root() + "/" + set; }

bool data_set_available(const std::string& set) {
  return std::ifstream(data_set_dir(set) + "/datasets.tsv").good();
}

bool missing_data_allowed() {
  const char* allow = std::getenv("TRISTEREO_ALLOW_MISSING_DATA");
  return allow != nullptr && std::string(allow) == "1";
}

}  // namespace tristereo::test
