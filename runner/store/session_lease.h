#pragma once
// One owner per session at a time. A run holds its session's row in `session_owners`
// (docs/DATABASE.md) from the session's first write to its end: a second `run --resume` of the
// same session is refused while the holder still runs, and takes the session over when the holder
// was killed or crashed (its row is left behind, but its process is gone: process_identity.h).
// Claiming is one write transaction, so of two resumes racing for an orphaned session exactly one
// wins.
#include <cstdint>
#include <optional>

#include "runner/store/process_identity.h"
#include "runner/store/result_store.h"

namespace glarelab {

class SessionLease {
 public:
  // Claims `session_id` for this process. Throws StoreError ("SQLite: FILE: session N is being run
  // by process P on host H since T") when its holder still runs, this process included.
  SessionLease(ResultStore& store, std::int64_t session_id);
  // Gives the session up (its row removed when it is still this process's).
  ~SessionLease();
  SessionLease(const SessionLease&) = delete;
  SessionLease& operator=(const SessionLease&) = delete;

  // The holder whose row was left behind by a process that no longer runs, when this claim took
  // the session over from it.
  const std::optional<ProcessIdentity>& taken_over_from() const { return taken_over_from_; }

 private:
  ResultStore& store_;
  std::int64_t session_id_;
  ProcessIdentity holder_;
  std::optional<ProcessIdentity> taken_over_from_;
};

}  // namespace glarelab
