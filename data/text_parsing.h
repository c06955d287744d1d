#pragma once
// Strict parsing of whitespace-separated text tables: every error names the file and line.

#include <fstream>
#include <string>
#include <vector>

namespace dslam {

// "path:line: message", the form every reader error takes.
std::string AtLine(const std::string& path, int line_no, const std::string& message);

// Splits on spaces and tabs.
std::vector<std::string> SplitFields(const std::string& line);

// Parses a finite double; throws std::runtime_error(AtLine(...)) naming the field otherwise.
double ParseDouble(const std::string& field, const std::string& path, int line_no, const std::string& what);
int ParseInt(const std::string& field, const std::string& path, int line_no, const std::string& what);

// Opens for reading or throws std::runtime_error naming the file.
std::ifstream OpenText(const std::string& path);

}  // namespace dslam
