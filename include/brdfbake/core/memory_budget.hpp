#pragma once
/// @file
/// The memory one allocation may take. Sizes read from file headers or asked for by a spec are
/// checked against this budget before anything is allocated, so a hostile header or a typo in a
/// resolution ends in a clear error (Error::Kind::Resource, exit status 4) instead of an
/// out-of-memory kill.

#include <cstdint>
#include <string>

namespace brdfbake {

/// The budget in bytes: the environment variable BRDFBAKE_MEMORY_LIMIT (bytes, or a number with
/// K, M or G, e.g. "8G") if set, else half of the machine's physical memory.
std::uint64_t memoryBudgetBytes();

/// Throws Error(Resource) "<what> needs N GiB, more than the memory budget of M GiB ..." if
/// `bytes` exceeds memoryBudgetBytes().
void requireWithinMemoryBudget(double bytes, const std::string& what);

/// "1.5 GiB", "320 MiB", "12 KiB", "100 bytes".
std::string formatBytes(double bytes);

}  // namespace brdfbake
