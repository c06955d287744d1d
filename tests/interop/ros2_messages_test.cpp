// The ROS 2 package ros2/dslam_msgs must describe exactly what `dslam serve` puts on the wire, which
// idl/dslam_msgs.idl defines: same messages, same fields in the same order with the same types (the wire
// format, XCDR1 without type information, is the fields in order). Field names are compared too, so
// that `ros2 topic echo` shows the names docs/serve.md documents.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace {

using Fields = std::vector<std::pair<std::string, std::string>>;  // (type in ROS 2 .msg spelling, name)

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << "cannot read " << path;
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// IDL type -> .msg type: "geometry_msgs::msg::Pose" -> "geometry_msgs/Pose", this package's own types
// without the package, primitives renamed as rosidl maps them.
std::string MsgType(std::string idl) {
  static const std::map<std::string, std::string> primitives = {
      {"double", "float64"}, {"float", "float32"}, {"boolean", "bool"}, {"int32", "int32"}, {"uint32", "uint32"},
      {"int64", "int64"},    {"uint64", "uint64"}, {"string", "string"}, {"uint8", "uint8"}, {"int8", "int8"}};
  bool sequence = false;
  const std::smatch m = [&] {
    std::smatch match;
    std::regex_match(idl, match, std::regex(R"(sequence<\s*([\w:]+)\s*>)"));
    return match;
  }();
  if (!m.empty()) {
    idl = m[1];
    sequence = true;
  }
  std::string type;
  if (const auto p = primitives.find(idl); p != primitives.end()) {
    type = p->second;
  } else {
    const std::smatch q = [&] {
      std::smatch match;
      std::regex_match(idl, match, std::regex(R"((\w+)::msg::(\w+))"));
      return match;
    }();
    EXPECT_FALSE(q.empty()) << "unexpected IDL type " << idl;
    type = q[1] == "dslam_msgs" ? std::string(q[2]) : std::string(q[1]) + "/" + std::string(q[2]);
  }
  return sequence ? type + "[]" : type;
}

// The structs of module dslam_msgs::msg in the IDL, each as its fields.
std::map<std::string, Fields> IdlStructs(const std::string& idl_text) {
  const std::string text = std::regex_replace(idl_text, std::regex("//[^\n]*"), "");  // comments may hold braces
  std::map<std::string, Fields> out;
  const std::regex struct_re(R"(struct\s+(\w+)\s*\{([^}]*)\})");
  const std::regex member_re(R"(^\s*([\w:<>\s]+?)\s+(\w+)\s*(\[(\d+)\])?\s*;)");
  for (std::sregex_iterator it(text.begin(), text.end(), struct_re), end; it != end; ++it) {
    Fields fields;
    std::istringstream body((*it)[2].str());
    for (std::string line; std::getline(body, line);) {
      std::smatch m;
      if (!std::regex_search(line, m, member_re)) continue;
      std::string type = MsgType(m[1]);
      if (m[4].matched) type += "[" + m[4].str() + "]";
      fields.emplace_back(type, m[2]);
    }
    out[(*it)[1]] = fields;
  }
  return out;
}

Fields MsgFields(const std::string& text) {
  Fields fields;
  std::istringstream in(text);
  const std::regex field_re(R"(^\s*([\w/]+(\[\d*\])?)\s+(\w+)\s*$)");
  for (std::string line; std::getline(in, line);) {
    line = line.substr(0, line.find('#'));
    std::smatch m;
    if (std::regex_match(line, m, field_re)) fields.emplace_back(m[1], m[3]);
  }
  return fields;
}

TEST(Ros2Messages, ThePackageAgreesWithTheIdlFieldByField) {
  const std::string root = DSLAM_SOURCE_DIR;
  const auto idl = IdlStructs(ReadFile(root + "/idl/dslam_msgs.idl"));
  ASSERT_EQ(idl.size(), 3u);
  for (const auto& [name, fields] : idl) {
    SCOPED_TRACE(name);
    ASSERT_FALSE(fields.empty());
    EXPECT_EQ(MsgFields(ReadFile(root + "/ros2/dslam_msgs/msg/" + name + ".msg")), fields);
  }
  // Spot checks of the mapping itself, so that a parser bug cannot make both sides agree on nothing.
  EXPECT_EQ(idl.at("ObjectMotion").back(), (std::pair<std::string, std::string>{"int32", "box_height"}));
  EXPECT_EQ(idl.at("ObjectMotion").at(6), (std::pair<std::string, std::string>{"float64[36]", "covariance"}));
  EXPECT_EQ(idl.at("ObjectMotionArray").back(), (std::pair<std::string, std::string>{"ObjectMotion[]", "objects"}));
  EXPECT_EQ(idl.at("Status").front(), (std::pair<std::string, std::string>{"std_msgs/Header", "header"}));
  // Every message of the package is built by its CMakeLists.txt.
  const std::string cmake = ReadFile(root + "/ros2/dslam_msgs/CMakeLists.txt");
  for (const auto& [name, fields] : idl) EXPECT_NE(cmake.find("\"msg/" + name + ".msg\""), std::string::npos) << name;
}

TEST(Ros2Messages, TheParsersSeeADifference) {
  const auto idl = IdlStructs("struct A {\n  double x;  // x_{k}\n  sequence<geometry_msgs::msg::Point> p;\n};\n");
  ASSERT_EQ(idl.at("A").size(), 2u);
  EXPECT_NE(MsgFields("float64 x\ngeometry_msgs/Point p\n"), idl.at("A"));
  EXPECT_EQ(MsgFields("float64 x  # comment\ngeometry_msgs/Point[] p\n"), idl.at("A"));
}

}  // namespace
