#include "artemis/core/log.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <atomic>

namespace artemis::log {
namespace {

std::atomic<Level> g_level{Level::kInfo};

spdlog::logger& logger() {
  // Logs go to stderr so that stdout stays clean for --json output.
  static const std::shared_ptr<spdlog::logger> kInstance = [] {
    auto l = spdlog::stderr_color_mt("artemis");
    l->set_pattern("[%H:%M:%S.%e] [%^%l%$] %v");
    l->set_level(spdlog::level::trace);
    return l;
  }();
  return *kInstance;
}

}  // namespace

void setLevel(Level level) {
  g_level = level;
}
Level level() {
  return g_level;
}

void write(Level level, std::string_view message) {
  if (level < g_level.load() || level == Level::kOff) return;
  switch (level) {
    case Level::kDebug: logger().debug(message); break;
    case Level::kInfo: logger().info(message); break;
    case Level::kWarn: logger().warn(message); break;
    case Level::kError: logger().error(message); break;
    case Level::kOff: break;
  }
}

}  // namespace artemis::log
