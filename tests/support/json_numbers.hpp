// The numbers of one array in a JSON file, for tests that compare with the
// data sets' own measurements (no JSON library is a dependency).
#pragma once

#include <string>
#include <vector>

namespace tristereo::test {

// The file's text; throws tristereo::Error when it cannot be read.
std::string read_text_file(const std::string& path);

// Finds each of `keys` (as "key") in turn, each after the previous one, from
// `from`, and returns every number of the array that follows the last one,
// flattened ([[1, 2], [3, 4]] -> 1 2 3 4). Empty when a key is absent.
// *end (optional) is set past that array.
std::vector<double> json_numbers_after(const std::string& text, const std::vector<std::string>& keys,
                                       std::size_t from = 0, std::size_t* end = nullptr);

}  // namespace tristereo::test
