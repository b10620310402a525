#include "runner/store/session_lease.h"

#include <sqlite3.h>

#include <string>

#include "runner/store/sqlite_statement.h"

namespace glarelab {
namespace {

using sqlite::Statement;
using sqlite::Transaction;

struct OwnerRow {
  ProcessIdentity process;
  std::string since_utc;
};

std::optional<OwnerRow> read_owner(const ResultStore& store, std::int64_t session_id) {
  Statement select(store.handle(), store.path(),
                   "SELECT pid, process_start_ticks, boot_id, host, since_utc FROM session_owners WHERE session_id = ?1",
                   "reading the owner of session " + std::to_string(session_id));
  select.bind(1, session_id);
  if (!select.step()) return std::nullopt;
  OwnerRow owner;
  owner.process.pid = select.int64(0);
  owner.process.start_ticks = select.int64(1);
  owner.process.boot_id = select.text(2);
  owner.process.host = select.text(3);
  owner.since_utc = select.text(4);
  return owner;
}

bool same_process(const ProcessIdentity& a, const ProcessIdentity& b) {
  return a.pid == b.pid && a.start_ticks == b.start_ticks && a.boot_id == b.boot_id && a.host == b.host;
}

}  // namespace

SessionLease::SessionLease(ResultStore& store, std::int64_t session_id)
    : store_(store), session_id_(session_id), holder_(this_process()) {
  const std::string what = "claiming session " + std::to_string(session_id);
  Transaction transaction(store.handle(), store.path(), what);
  if (const std::optional<OwnerRow> owner = read_owner(store, session_id)) {
    // This very process holding it already is a second run of one session in one process: refused
    // like any other live holder.
    if (same_process(owner->process, holder_) || still_running(owner->process))
      throw StoreError("SQLite: " + store.path() + ": session " + std::to_string(session_id) + " is being run by " +
                       describe(owner->process) + " since " + owner->since_utc +
                       ": wait for it to end, or end it (Ctrl-C or Escape keep its trials), then resume");
    taken_over_from_ = owner->process;
  }
  Statement upsert(store.handle(), store.path(),
                   "INSERT OR REPLACE INTO session_owners (session_id, pid, process_start_ticks, boot_id, host, since_utc) "
                   "VALUES (?1, ?2, ?3, ?4, ?5, ?6)",
                   what);
  upsert.bind(1, session_id);
  upsert.bind(2, holder_.pid);
  upsert.bind(3, holder_.start_ticks);
  upsert.bind(4, holder_.boot_id);
  upsert.bind(5, holder_.host);
  upsert.bind(6, utc_now_iso8601());
  upsert.step_done();
  transaction.commit();
}

SessionLease::~SessionLease() {
  // Never throws: a row this process failed to remove is taken over by the next resume, because
  // this process will have ended by then.
  try {
    Statement remove(store_.handle(), store_.path(),
                     "DELETE FROM session_owners WHERE session_id = ?1 AND pid = ?2 AND process_start_ticks = ?3 "
                     "AND boot_id = ?4",
                     "releasing session " + std::to_string(session_id_));
    remove.bind(1, session_id_);
    remove.bind(2, holder_.pid);
    remove.bind(3, holder_.start_ticks);
    remove.bind(4, holder_.boot_id);
    remove.step_done();
  } catch (const StoreError&) {
  }
}

}  // namespace glarelab
