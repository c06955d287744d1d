#include "data/runtime_module.h"

#include <dlfcn.h>
#include <unistd.h>

#include <climits>
#include <map>
#include <mutex>
#include <stdexcept>
#include <vector>

#ifndef DSLAM_MODULE_BUILD_DIR
#define DSLAM_MODULE_BUILD_DIR ""
#endif

namespace dslam {
namespace {

std::string FileName(const std::string& name) { return "lib" + name + ".so"; }

std::string ExecutableDir() {
  char path[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", path, sizeof(path) - 1);
  if (n <= 0) return {};
  const std::string exe(path, static_cast<size_t>(n));
  const size_t slash = exe.rfind('/');
  return slash == std::string::npos ? std::string() : exe.substr(0, slash);
}

std::vector<std::string> SearchDirs() {
  std::vector<std::string> dirs;
  const std::string exe_dir = ExecutableDir();
  if (!exe_dir.empty()) {
    dirs.push_back(exe_dir);
    const size_t slash = exe_dir.rfind('/');
    if (slash != std::string::npos && slash > 0) dirs.push_back(exe_dir.substr(0, slash));
  }
  if (*DSLAM_MODULE_BUILD_DIR) dirs.push_back(DSLAM_MODULE_BUILD_DIR);
  return dirs;
}

}  // namespace

void* RuntimeModuleSymbol(const std::string& name, const char* symbol) {
  static std::mutex mutex;
  static std::map<std::string, void*> handles;  // never closed: their functions may be in use until exit
  std::lock_guard<std::mutex> lock(mutex);
  void*& handle = handles[name];
  std::string tried, reasons;
  if (!handle) {
    for (const std::string& dir : SearchDirs()) {
      const std::string path = dir + "/" + FileName(name);
      tried += (tried.empty() ? "" : ", ") + dir;
      if (access(path.c_str(), R_OK) != 0) continue;
      handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (handle) break;
      const char* error = dlerror();
      reasons += std::string("; ") + (error ? error : path + ": cannot be loaded");
    }
  }
  if (!handle)
    throw std::runtime_error(FileName(name) + " (an optional part of dslam) was not found in " +
                             (tried.empty() ? std::string("any folder") : tried) + reasons +
                             "; build it (cmake --build build) or copy it beside the dslam executable");
  dlerror();
  void* address = dlsym(handle, symbol);
  if (!address) {
    const char* error = dlerror();
    throw std::runtime_error(FileName(name) + " has no " + symbol + (error ? std::string(": ") + error : std::string()) +
                             " (a library from another build of dslam?)");
  }
  return address;
}

bool RuntimeModuleLoaded(const std::string& name) {
  for (const std::string& dir : SearchDirs()) {
    void* handle = dlopen((dir + "/" + FileName(name)).c_str(), RTLD_NOW | RTLD_NOLOAD);
    if (handle) {
      dlclose(handle);  // drops only the reference RTLD_NOLOAD took
      return true;
    }
  }
  return false;
}

}  // namespace dslam
