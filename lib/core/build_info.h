#pragma once
// What was built: for sidecars and tables.
namespace vpm {
const char* git_revision();   // short hash at configure time, or "unknown"
const char* vpm_version();
}  // namespace vpm
