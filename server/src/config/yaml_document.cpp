#include "config/yaml_document.hpp"

#include <yaml-cpp/eventhandler.h>

#include <map>
#include <sstream>
#include <vector>

#include "config/config_error.hpp"
#include "config/yaml_reader.hpp"

namespace hapticd::server {
struct MarkSetter {};
}  // namespace hapticd::server

// yaml-cpp sets a node's position only while it parses; a copy made through its public interface has none, and
// every config error names its line. as_if is a friend of Node (all its specialisations are): this one, for a
// tag type of ours, gives a copy the position of the node it copies.
template <>
struct YAML::as_if<hapticd::server::MarkSetter, void> {
  static void set(YAML::Node& node, const YAML::Mark& mark) {
    node.EnsureNodeExists();
    node.m_pNode->set_mark(mark);
  }
};

namespace hapticd::server {
namespace {

// Counts the values of a document from the parser's events, an alias as the size of what it names; throws once
// the count passes kMaxYamlNodes (the parser stops there: nothing is built of the rest).
class NodeCounter final : public YAML::EventHandler {
 public:
  explicit NodeCounter(const std::string& file) : file_(file) {}
  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t anchor) override { leaf(mark, anchor, 1); }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t anchor) override {
    // An alias inside the very value its anchor names would make the document a cycle (yaml-cpp builds it as
    // one, and every walk of it recurses without end).
    for (const Open& o : open_)
      if (o.anchor == anchor)
        throw ConfigError(file_, mark.is_null() ? 0 : mark.line + 1, "",
                          "an alias inside the value its anchor names (the value would contain itself); refer to "
                          "an anchor only after its value has ended");
    const auto found = sizes_.find(anchor);
    leaf(mark, 0, found == sizes_.end() ? 1 : found->second);
  }
  void OnScalar(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor, const std::string&) override {
    leaf(mark, anchor, 1);
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                       YAML::EmitterStyle::value) override {
    open(mark, anchor);
  }
  void OnSequenceEnd() override { close(); }
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                  YAML::EmitterStyle::value) override {
    open(mark, anchor);
  }
  void OnMapEnd() override { close(); }

 private:
  void add(const YAML::Mark& mark, std::size_t n) {
    count_ += n;
    if (count_ > kMaxYamlNodes)
      throw ConfigError(file_, mark.is_null() ? 0 : mark.line + 1, "",
                        "the session has more than " + std::to_string(kMaxYamlNodes) +
                            " values (aliases counted where they are used); a session file holds far fewer");
  }
  void leaf(const YAML::Mark& mark, YAML::anchor_t anchor, std::size_t n) {
    add(mark, n);
    if (anchor != 0) sizes_[anchor] = n;
  }
  void open(const YAML::Mark& mark, YAML::anchor_t anchor) {
    add(mark, 1);
    if (open_.size() >= kMaxYamlDepth)
      throw ConfigError(file_, mark.is_null() ? 0 : mark.line + 1, "",
                        "the session nests lists and mappings more than " + std::to_string(kMaxYamlDepth) +
                            " deep; a session file nests far less");
    open_.push_back({anchor, count_ - 1});
  }
  void close() {
    if (open_.empty()) return;
    const Open o = open_.back();
    open_.pop_back();
    if (o.anchor != 0) sizes_[o.anchor] = count_ - o.start;
  }

  struct Open {
    YAML::anchor_t anchor;
    std::size_t start;
  };
  const std::string& file_;
  std::size_t count_ = 0;
  std::vector<Open> open_;
  std::map<YAML::anchor_t, std::size_t> sizes_;
};

void check_duplicate_keys(const YAML::Node& node, const std::string& file, const std::string& path) {
  if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i)
      check_duplicate_keys(node[i], file, path + "[" + std::to_string(i) + "]");
    return;
  }
  if (!node.IsMap()) return;
  std::map<std::string, int> seen;  // key -> its line
  for (const auto& entry : node) {
    if (!entry.first.IsScalar()) continue;
    const std::string& key = entry.first.Scalar();
    const std::string key_path = path.empty() ? key : path + "." + key;
    const int line = line_of(entry.first);
    if (const auto [at, fresh] = seen.emplace(key, line); !fresh)
      throw ConfigError(file, line, key_path,
                        "the key '" + key + "' is given twice in one mapping (lines " + std::to_string(at->second) +
                            " and " + std::to_string(line) + "); give it once");
    check_duplicate_keys(entry.second, file, key_path);
  }
}

// A copy that shares no node with the original or within itself, every node with the original's position.
YAML::Node unshared_copy(const YAML::Node& node) {
  YAML::Node copy;
  switch (node.Type()) {
    case YAML::NodeType::Scalar:
      copy = YAML::Node(node.Scalar());
      break;
    case YAML::NodeType::Sequence:
      copy = YAML::Node(YAML::NodeType::Sequence);
      for (const auto& element : node) copy.push_back(unshared_copy(element));
      break;
    case YAML::NodeType::Map:
      copy = YAML::Node(YAML::NodeType::Map);
      for (const auto& entry : node) copy.force_insert(unshared_copy(entry.first), unshared_copy(entry.second));
      break;
    case YAML::NodeType::Null:
      copy = YAML::Node(YAML::NodeType::Null);
      break;
    case YAML::NodeType::Undefined:
      return node;
  }
  if (!node.Tag().empty() && node.Tag() != "?" && node.Tag() != "!") copy.SetTag(node.Tag());
  YAML::as_if<MarkSetter, void>::set(copy, node.Mark());
  return copy;
}

}  // namespace

YAML::Node load_yaml_document(const std::string& text, const std::string& file) {
  try {
    {
      std::istringstream in(text);
      YAML::Parser parser(in);
      NodeCounter counter(file);
      (void)parser.HandleNextDocument(counter);
    }
    const YAML::Node root = YAML::Load(text);
    check_duplicate_keys(root, file, "");
    return unshared_copy(root);
  } catch (const YAML::ParserException& e) {
    throw ConfigError(file, e.mark.is_null() ? 0 : e.mark.line + 1, "", "YAML syntax error: " + e.msg);
  }
}

}  // namespace hapticd::server
