#pragma once
// The results store's SQLite statements: a prepared statement finalized on every path and a write
// transaction rolled back unless committed, each naming the database file and what the statement
// was for in its StoreError (runner/store/result_store.cpp).
#include <sqlite3.h>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include "core/errors.h"

namespace glarelab::sqlite {

[[noreturn]] inline void fail(sqlite3* db, const std::string& path, const std::string& what) {
  const char* message = db != nullptr ? sqlite3_errmsg(db) : "out of memory";
  throw StoreError("SQLite: " + path + ": " + what + ": " + message);
}

// A prepared statement that is finalized on every path, reporting errors with the file name
// and what the statement was for.
class Statement {
 public:
  Statement(sqlite3* db, const std::string& path, const char* sql, std::string what)
      : db_(db), path_(path), what_(std::move(what)) {
    if (sqlite3_prepare_v2(db_, sql, -1, &stmt_, nullptr) != SQLITE_OK) fail(db_, path_, what_);
  }
  ~Statement() { sqlite3_finalize(stmt_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  void bind(int column, std::int64_t value) { check(sqlite3_bind_int64(stmt_, column, value)); }
  void bind(int column, int value) { check(sqlite3_bind_int(stmt_, column, value)); }
  void bind(int column, double value) { check(sqlite3_bind_double(stmt_, column, value)); }
  void bind(int column, const std::string& value) {
    check(sqlite3_bind_text64(stmt_, column, value.data(), value.size(), SQLITE_TRANSIENT, SQLITE_UTF8));
  }
  void bind_null(int column) { check(sqlite3_bind_null(stmt_, column)); }
  // Empty text stands for "not recorded" in the records (finished_utc, staircase).
  void bind_text_or_null(int column, const std::string& value) {
    if (value.empty()) {
      bind_null(column);
    } else {
      bind(column, value);
    }
  }
  template <typename T>
  void bind(int column, const std::optional<T>& value) {
    if (value) {
      bind(column, *value);
    } else {
      bind_null(column);
    }
  }

  // True while there is a row to read; false when done.
  bool step() {
    const std::optional<bool> row = step_unless_busy();
    if (!row) fail(db_, path_, what_);
    return *row;
  }
  // As step(), but nothing where SQLite refused the statement's lock at once (SQLITE_BUSY), for a
  // caller that tries it again itself.
  std::optional<bool> step_unless_busy() {
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    if (rc == SQLITE_BUSY) return std::nullopt;
    fail(db_, path_, what_);
  }
  void step_done() {
    if (step()) throw StoreError("SQLite: " + path_ + ": " + what_ + ": statement returned rows");
  }
  void reset() {
    sqlite3_reset(stmt_);
    sqlite3_clear_bindings(stmt_);
  }

  bool is_null(int column) const { return sqlite3_column_type(stmt_, column) == SQLITE_NULL; }
  std::int64_t int64(int column) const { return sqlite3_column_int64(stmt_, column); }
  int integer(int column) const { return sqlite3_column_int(stmt_, column); }
  double real(int column) const { return sqlite3_column_double(stmt_, column); }
  std::string text(int column) const {
    const auto* data = reinterpret_cast<const char*>(sqlite3_column_text(stmt_, column));
    if (data == nullptr) return {};
    return std::string(data, static_cast<std::size_t>(sqlite3_column_bytes(stmt_, column)));
  }
  std::optional<double> optional_real(int column) const {
    if (is_null(column)) return std::nullopt;
    return real(column);
  }
  std::optional<int> optional_integer(int column) const {
    if (is_null(column)) return std::nullopt;
    return integer(column);
  }

 private:
  void check(int rc) {
    if (rc != SQLITE_OK) fail(db_, path_, what_ + " (binding parameters)");
  }

  sqlite3* db_;
  const std::string& path_;
  std::string what_;
  sqlite3_stmt* stmt_ = nullptr;
};

inline void exec(sqlite3* db, const std::string& path, const char* sql, const std::string& what) {
  char* message = nullptr;
  if (sqlite3_exec(db, sql, nullptr, nullptr, &message) != SQLITE_OK) {
    const std::string text = message != nullptr ? message : sqlite3_errmsg(db);
    sqlite3_free(message);
    throw StoreError("SQLite: " + path + ": " + what + ": " + text);
  }
}

// BEGIN IMMEDIATE takes the write lock up front, so a second writer waits (busy_timeout) at
// the start rather than failing halfway through. Rolls back unless commit() was reached.
class Transaction {
 public:
  Transaction(sqlite3* db, const std::string& path, const std::string& what) : db_(db), path_(path), what_(what) {
    exec(db_, path_, "BEGIN IMMEDIATE", "starting a transaction for " + what_);
  }
  ~Transaction() {
    if (!committed_) sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
  }
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;
  void commit() {
    exec(db_, path_, "COMMIT", "committing " + what_);
    committed_ = true;
  }

 private:
  sqlite3* db_;
  const std::string& path_;
  std::string what_;
  bool committed_ = false;
};

inline int read_user_version(sqlite3* db, const std::string& path) {
  Statement statement(db, path, "PRAGMA user_version", "reading the schema version");
  if (!statement.step()) throw StoreError("SQLite: " + path + ": reading the schema version: no result");
  return statement.integer(0);
}

}  // namespace glarelab::sqlite
