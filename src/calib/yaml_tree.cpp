#include "src/calib/yaml_tree.hpp"

#include <cstddef>

namespace tristereo::calib_detail {

namespace {

struct Src {
  int number;
  int indent;
  std::string text;  // trimmed, comment removed
};

// A '#' starts a comment at the line's start or after a blank, outside quotes.
std::string strip_comment(const std::string& s) {
  char quote = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '#' && (i == 0 || s[i - 1] == ' ' || s[i - 1] == '\t')) {
      return s.substr(0, i);
    }
  }
  return s;
}

int bracket_balance(const std::string& s) {
  int depth = 0;
  for (char c : s) depth += (c == '[') - (c == ']');
  return depth;
}

class Parser {
 public:
  Parser(const std::string& path, std::vector<Src> src) : path_(path), src_(std::move(src)) {}

  YamlNode document() {
    if (src_.empty()) fail(ErrorCode::kCorruptFile, path_, 0, "", "no YAML content");
    YamlNode root = block(src_[0].indent);
    if (pos_ < src_.size())
      fail(ErrorCode::kCorruptFile, path_, src_[pos_].number, "", "unexpected indentation of '" + src_[pos_].text + "'");
    return root;
  }

 private:
  bool is_item(const Src& s) const { return s.text == "-" || s.text.rfind("- ", 0) == 0; }

  // A value that opens a flow sequence continues over the next lines until
  // its brackets close.
  std::string flow_value(std::string value, int line) {
    while (bracket_balance(value) > 0) {
      if (pos_ >= src_.size()) fail(ErrorCode::kCorruptFile, path_, line, "", "a '[' sequence has no closing ']'");
      value += " " + src_[pos_++].text;
    }
    if (bracket_balance(value) < 0) fail(ErrorCode::kCorruptFile, path_, line, "", "unbalanced ']'");
    return value;
  }

  YamlNode block(int indent) {
    if (is_item(src_[pos_])) return sequence(indent);
    return mapping(indent);
  }

  YamlNode sequence(int indent) {
    YamlNode seq;
    seq.kind = YamlNode::kSeq;
    seq.line = src_[pos_].number;
    while (pos_ < src_.size() && src_[pos_].indent == indent && is_item(src_[pos_])) {
      const Src s = src_[pos_++];
      const std::string rest = s.text.size() > 1 ? s.text.substr(2) : std::string();
      YamlNode item;
      item.line = s.number;
      if (rest.empty()) {
        if (pos_ < src_.size() && src_[pos_].indent > indent) item = block(src_[pos_].indent);
      } else if (rest.find(": ") != std::string::npos || (rest.back() == ':' && rest[0] != '[')) {
        fail(ErrorCode::kCorruptFile, path_, s.number, "", "mappings inside sequence items are not supported");
      } else {
        item.text = flow_value(rest, s.number);
      }
      seq.items.push_back(std::move(item));
    }
    return seq;
  }

  YamlNode mapping(int indent) {
    YamlNode map;
    map.kind = YamlNode::kMap;
    map.line = src_[pos_].number;
    while (pos_ < src_.size() && src_[pos_].indent == indent && !is_item(src_[pos_])) {
      const Src s = src_[pos_++];
      std::size_t colon = s.text.find(": ");
      if (colon == std::string::npos && !s.text.empty() && s.text.back() == ':') colon = s.text.size() - 1;
      if (colon == std::string::npos || colon == 0)
        fail(ErrorCode::kCorruptFile, path_, s.number, "", "expected 'key: value', got '" + s.text + "'");
      std::string key = trim(s.text.substr(0, colon));
      if (key.size() >= 2 && (key[0] == '"' || key[0] == '\'') && key.back() == key[0])
        key = key.substr(1, key.size() - 2);
      std::string value = trim(s.text.substr(colon + 1));
      // A local tag such as !!opencv-matrix says nothing these formats need.
      if (value.rfind("!", 0) == 0) {
        const std::size_t sp = value.find(' ');
        value = sp == std::string::npos ? std::string() : trim(value.substr(sp + 1));
      }
      YamlNode child;
      child.line = s.number;
      if (value.empty()) {
        // Block child: deeper lines, or a sequence at the key's own indent.
        if (pos_ < src_.size() &&
            (src_[pos_].indent > indent || (src_[pos_].indent == indent && is_item(src_[pos_]))))
          child = block(src_[pos_].indent);
        child.line = s.number;
      } else {
        child.text = flow_value(value, s.number);
      }
      for (const auto& f : map.fields)
        if (f.first == key) fail(ErrorCode::kCorruptFile, path_, s.number, key, "appears twice");
      map.fields.emplace_back(key, std::move(child));
    }
    return map;
  }

  const std::string& path_;
  std::vector<Src> src_;
  std::size_t pos_ = 0;
};

}  // namespace

const YamlNode* YamlNode::find(const std::string& key) const {
  for (const auto& f : fields)
    if (f.first == key) return &f.second;
  return nullptr;
}

YamlNode parse_yaml_tree(const std::string& path, const std::vector<Line>& lines) {
  std::vector<Src> src;
  for (const Line& l : lines) {
    if (l.text.find('\t') != std::string::npos && l.text.find_first_not_of(" \t") != std::string::npos &&
        l.text.find('\t') < l.text.find_first_not_of(" \t"))
      fail(ErrorCode::kCorruptFile, path, l.number, "", "a tab in the indentation (YAML indents with spaces)");
    const std::string t = trim(strip_comment(l.text));
    if (t.empty() || t[0] == '%' || t == "---") continue;
    if (t == "...") break;
    src.push_back({l.number, static_cast<int>(l.text.find_first_not_of(' ')), t});
  }
  return Parser(path, std::move(src)).document();
}

const YamlNode& yaml_get(const YamlNode& map, const std::string& key, const std::string& path,
                         const std::string& where) {
  const YamlNode* n = map.kind == YamlNode::kMap ? map.find(key) : nullptr;
  if (n == nullptr) fail(ErrorCode::kCorruptFile, path, map.line, where, "missing");
  return *n;
}

std::vector<double> yaml_numbers(const YamlNode& node, const std::string& path, const std::string& where) {
  if (node.kind == YamlNode::kMap)
    fail(ErrorCode::kCorruptFile, path, node.line, where, "expected numbers, got a mapping");
  if (node.kind == YamlNode::kScalar) return parse_numbers(node.text, path, node.line, where);
  std::vector<double> out;
  for (const YamlNode& item : node.items) {
    const std::vector<double> v = yaml_numbers(item, path, where);
    out.insert(out.end(), v.begin(), v.end());
  }
  return out;
}

std::vector<double> yaml_numbers(const YamlNode& node, std::size_t count, const std::string& path,
                                 const std::string& where) {
  const std::vector<double> v = yaml_numbers(node, path, where);
  if (v.size() != count)
    fail(ErrorCode::kCorruptFile, path, node.line, where,
         "expected " + std::to_string(count) + " numbers, got " + std::to_string(v.size()));
  return v;
}

std::string yaml_string(const YamlNode& node, const std::string& path, const std::string& where) {
  if (node.kind != YamlNode::kScalar) fail(ErrorCode::kCorruptFile, path, node.line, where, "expected a single value");
  std::string t = trim(node.text);
  if (t.size() >= 2 && (t[0] == '"' || t[0] == '\'') && t.back() == t[0]) t = t.substr(1, t.size() - 2);
  return t;
}

}  // namespace tristereo::calib_detail
