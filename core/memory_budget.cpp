#include <brdfbake/core/error.hpp>
#include <brdfbake/core/memory_budget.hpp>
#include <brdfbake/core/printable.hpp>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <optional>
#include <sstream>
#include <string>

namespace brdfbake {

namespace {
std::uint64_t physicalMemoryBytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), pageSize = ::sysconf(_SC_PAGESIZE);
  if (pages <= 0 || pageSize <= 0) return std::uint64_t{8} << 30;
  return static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(pageSize);
}

std::optional<std::uint64_t> parseLimit(const char* text) {
  char* end = nullptr;
  const double value = std::strtod(text, &end);
  if (end == text || !(value > 0) || !std::isfinite(value)) return std::nullopt;
  double scale = 1.0;
  switch (*end) {
    case 'k':
    case 'K':
      scale = 1024.0;
      ++end;
      break;
    case 'm':
    case 'M':
      scale = 1024.0 * 1024.0;
      ++end;
      break;
    case 'g':
    case 'G':
      scale = 1024.0 * 1024.0 * 1024.0;
      ++end;
      break;
    default:
      break;
  }
  if (*end != '\0' && std::string(end) != "B" && std::string(end) != "iB") return std::nullopt;
  return static_cast<std::uint64_t>(std::min(value * scale, 1.8e19));
}
}  // namespace

std::uint64_t memoryBudgetBytes() {
  if (const char* limit = std::getenv("BRDFBAKE_MEMORY_LIMIT")) {
    if (const auto parsed = parseLimit(limit)) return *parsed;
    throw Error(Error::Kind::InvalidArgument,
                std::string("BRDFBAKE_MEMORY_LIMIT: expected bytes or a number with K, M or G (e.g. 8G), got \"") +
                    printable(limit, 40) + "\"");
  }
  return physicalMemoryBytes() / 2;
}

std::string formatBytes(double bytes) {
  std::ostringstream out;
  out.precision(3);
  if (bytes >= 1024.0 * 1024 * 1024)
    out << bytes / (1024.0 * 1024 * 1024) << " GiB";
  else if (bytes >= 1024.0 * 1024)
    out << bytes / (1024.0 * 1024) << " MiB";
  else if (bytes >= 1024.0)
    out << bytes / 1024.0 << " KiB";
  else
    out << bytes << " bytes";
  return out.str();
}

void requireWithinMemoryBudget(double bytes, const std::string& what) {
  const std::uint64_t budget = memoryBudgetBytes();
  if (!(bytes <= static_cast<double>(budget))) {
    throw Error(Error::Kind::Resource,
                what + " needs " + formatBytes(bytes) + ", more than the memory budget of " +
                    formatBytes(static_cast<double>(budget)) +
                    (std::getenv("BRDFBAKE_MEMORY_LIMIT")
                         ? " (BRDFBAKE_MEMORY_LIMIT)"
                         : " (half the machine's memory; set BRDFBAKE_MEMORY_LIMIT to change it)"));
  }
}

}  // namespace brdfbake
