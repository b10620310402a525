#pragma once
// Schema migrations of a results database, in order: kSchemaMigrations[i] upgrades user_version i
// to i + 1 (runner/store/result_store.cpp runs each in a transaction with the version bump).
#include "core/result_records.h"

namespace glarelab {

// One script per schema version (a static_assert in the .cpp checks the count against
// kResultsSchemaVersion).
extern const char* const kSchemaMigrations[kResultsSchemaVersion];

}  // namespace glarelab
