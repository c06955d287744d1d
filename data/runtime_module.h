#pragma once
// Optional parts of dslam built as shared libraries of their own and loaded on first use. PCL (LiDAR
// masks and scan registration) and OpenCV's contrib filters pull in dozens of libraries whose loading and
// relocation cost a process about 0.1 s each at start-up; a process that never clusters a scan or filters
// a disparity never maps them.

#include <stdexcept>
#include <string>

namespace dslam {

// The address of `symbol` in lib<name>.so, loaded once per process. The library is looked for beside the
// running executable, in that folder's parent, then in the build tree dslam was built in (where tests and
// benchmarks find it). Throws std::runtime_error naming the library, the folders searched and the loader's
// reason when it is missing or lacks the symbol.
void* RuntimeModuleSymbol(const std::string& name, const char* symbol);

// Whether lib<name>.so is already mapped into this process (tests: a command that does not need a module
// never loads it).
bool RuntimeModuleLoaded(const std::string& name);

// A module exports one function, `extern "C" const Table* <entry>()`, returning a table of its functions
// that starts with this header. A table of another version or size (a module from another build of dslam)
// is refused rather than called.
struct ModuleTableHeader {
  int version = 0;
  int size = 0;
};

// The table of lib<name>.so, loaded on first use; throws std::runtime_error when the module is missing,
// lacks the entry or is from another build.
template <class Table>
const Table& RuntimeModuleTable(const std::string& name, const char* entry) {
  static const Table* table = [&] {
    using Entry = const Table* (*)();
    const Table* t = reinterpret_cast<Entry>(RuntimeModuleSymbol(name, entry))();
    if (!t || t->header.version != Table::kVersion || t->header.size != static_cast<int>(sizeof(Table)))
      throw std::runtime_error("lib" + name + ".so is from another build of dslam: rebuild it (cmake --build build)");
    return t;
  }();
  return *table;
}

}  // namespace dslam
