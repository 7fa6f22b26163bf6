#include "support/json_numbers.hpp"

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "tristereo/status.hpp"

namespace tristereo::test {

std::string read_text_file(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw Error(ErrorCode::kIoError, "cannot open " + path);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

std::vector<double> json_numbers_after(const std::string& text, const std::vector<std::string>& keys,
                                       std::size_t from, std::size_t* end) {
  std::size_t pos = from;
  for (const std::string& k : keys) {
    pos = text.find("\"" + k + "\"", pos);
    if (pos == std::string::npos) return {};
    pos += k.size() + 2;
  }
  std::vector<double> out;
  pos = text.find('[', pos);
  if (pos == std::string::npos) return {};
  int depth = 0;
  for (std::size_t i = pos; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '[') ++depth;
    else if (c == ']') {
      if (--depth == 0) {
        if (end) *end = i + 1;
        break;
      }
    } else if (c == '-' || (c >= '0' && c <= '9')) {
      char* e = nullptr;
      out.push_back(std::strtod(text.c_str() + i, &e));
      i = static_cast<std::size_t>(e - text.c_str()) - 1;
    }
  }
  return out;
}

}  // namespace tristereo::test
