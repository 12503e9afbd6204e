// SPDX-License-Identifier: Apache-2.0
#include "coxswain/drivers/camera/image_io.hpp"

#include <dlfcn.h>
#include <unistd.h>

#include <array>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <system_error>

namespace coxswain::drivers::camera {
namespace fs = std::filesystem;

namespace {

constexpr const char* kModuleFile = "libcoxswain_image_io.so";
constexpr const char* kEntry = "coxswain_image_io_module";

struct LoadedImageIo {
  const ImageIoModule* module = nullptr;
  std::string error;
};

fs::path image_io_executable_dir() {
  std::array<char, 4096> buf{};
  const ssize_t n = ::readlink("/proc/self/exe", buf.data(), buf.size() - 1);
  if (n <= 0) return {};
  return fs::path(std::string(buf.data(), static_cast<std::size_t>(n))).parent_path();
}

std::vector<fs::path> image_io_candidates() {
  std::vector<fs::path> candidates;
  if (const char* env = std::getenv("COXSWAIN_IMAGE_IO_MODULE"); env != nullptr && *env != 0) {
    candidates.emplace_back(env);
  } else {
    const fs::path exe = image_io_executable_dir();
    if (!exe.empty()) {
      candidates.push_back(exe / kModuleFile);
      candidates.push_back(exe / ".." / "lib" / "coxswain" / kModuleFile);
    }
#ifdef COXSWAIN_IMAGE_IO_BUILD_PATH
    candidates.emplace_back(COXSWAIN_IMAGE_IO_BUILD_PATH);
#endif
  }
  return candidates;
}

/// The first candidate that exists, or empty with the paths tried.
fs::path find_image_io_module(std::string& tried) {
  for (const fs::path& p : image_io_candidates()) {
    std::error_code ec;
    if (fs::exists(p, ec)) return p;
    tried += (tried.empty() ? "" : ", ") + p.string();
  }
  return {};
}

std::string image_io_not_installed(const std::string& tried) {
  return std::string("the image-I/O module ") + kModuleFile + " is not installed (looked at " +
         (tried.empty() ? "nothing" : tried) + "; COXSWAIN_IMAGE_IO_MODULE names it)";
}

LoadedImageIo load_image_io() {
  LoadedImageIo out;
  std::string tried;
  const fs::path p = find_image_io_module(tried);
  if (p.empty()) {
    out.error = image_io_not_installed(tried);
    return out;
  }
  {
    void* handle = ::dlopen(p.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      const char* why = ::dlerror();
      out.error = "cannot load " + p.string() + ": " + (why != nullptr ? why : "dlopen failed");
      return out;
    }
    // The module stays loaded for the life of the process (its objects may outlive any owner).
    using Entry = const ImageIoModule* (*)();
    auto entry = reinterpret_cast<Entry>(::dlsym(handle, kEntry));
    const ImageIoModule* m = entry != nullptr ? entry() : nullptr;
    if (m == nullptr || m->abi_version != ImageIoModule::kAbiVersion || m->read_image == nullptr ||
        m->encode_jpeg == nullptr || m->new_capture == nullptr) {
      out.error = p.string() + " is not this build's image-I/O module";
      return out;
    }
    out.module = m;
    return out;
  }
}

}  // namespace

const ImageIoModule* image_io(std::string* error) {
  static std::once_flag once;
  static LoadedImageIo loaded;
  std::call_once(once, [] { loaded = load_image_io(); });
  if (loaded.module == nullptr && error != nullptr) *error = loaded.error;
  return loaded.module;
}

bool image_io_installed(std::string* error) {
  std::string tried;
  if (!find_image_io_module(tried).empty()) return true;
  if (error != nullptr) *error = image_io_not_installed(tried);
  return false;
}

cv::Mat read_image(const std::string& path, std::string* error) {
  const ImageIoModule* m = image_io(error);
  if (m == nullptr) return {};
  return m->read_image(path);
}

std::unique_ptr<Capture> make_capture(std::string& error) {
  const ImageIoModule* m = image_io(&error);
  if (m == nullptr) return nullptr;
  return std::unique_ptr<Capture>(m->new_capture());
}

}  // namespace coxswain::drivers::camera
