#include "backend.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <stdexcept>

// Defined by backend_export.cpp when a program links the LibTorch half itself; null otherwise.
extern "C" const eitbench::LearnedBackend* eitbench_learned_backend() __attribute__((weak));

namespace eitbench {
namespace {

constexpr const char* kModuleName = "libeitbench_learned_torch.so";

// Where the module may be, in order: EITBENCH_LEARNED_MODULE; beside the program (or shared
// library) that holds this code, and in ../lib from it (an installed tree: bin/, lib/); the
// build tree and the install prefix this build was configured with.
std::vector<std::string> module_candidates() {
  std::vector<std::string> out;
  if (const char* path = std::getenv("EITBENCH_LEARNED_MODULE"); path && *path) {
    out.push_back(path);
    return out;  // asked for: that one or none
  }
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&module_candidates), &info) && info.dli_fname) {
    std::error_code error;
    const auto self = std::filesystem::canonical(info.dli_fname, error);
    if (!error) {
      out.push_back((self.parent_path() / kModuleName).string());
      out.push_back((self.parent_path().parent_path() / "lib" / kModuleName).string());
    }
  }
#ifdef EITBENCH_LEARNED_MODULE_BUILD
  out.push_back(EITBENCH_LEARNED_MODULE_BUILD);
#endif
#ifdef EITBENCH_LEARNED_MODULE_INSTALL
  out.push_back(EITBENCH_LEARNED_MODULE_INSTALL);
#endif
  return out;
}

const LearnedBackend* load_module() {
  using Entry = const LearnedBackend* (*)();
  std::string tried;
  for (const std::string& path : module_candidates()) {
    std::error_code error;
    if (!std::filesystem::exists(path, error)) {
      tried += "\n  " + path + ": no such file";
      continue;
    }
    // RTLD_GLOBAL: LibTorch's libraries join the process as if linked (their own lookups of
    // OpenMP and the BLAS then see what the program loaded).
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_GLOBAL);
    if (!handle) {
      tried += "\n  " + path + ": " + dlerror();
      continue;
    }
    if (const auto entry = reinterpret_cast<Entry>(dlsym(handle, kLearnedBackendSymbol)))
      return entry();
    tried += "\n  " + path + ": no " + kLearnedBackendSymbol;
  }
  throw std::runtime_error(
      "the learned reconstructor's LibTorch module could not be loaded (set "
      "EITBENCH_LEARNED_MODULE to its path, or reinstall eitbench); tried:" +
      tried);
}

}  // namespace

const LearnedBackend& learned_backend() {
  static std::once_flag once;
  static const LearnedBackend* backend = nullptr;
  std::call_once(once, [] {
    backend = eitbench_learned_backend ? eitbench_learned_backend() : load_module();
  });
  return *backend;
}

}  // namespace eitbench
