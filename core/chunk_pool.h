#pragma once
// Worker threads started once per process that run the chunks of parallel_chunks (parallel_for.h).
//
// run_chunks(chunks, run_chunk) calls run_chunk(0) .. run_chunk(chunks - 1), each exactly once,
// and returns when all have returned. The caller takes chunks as the workers do, so the call
// finishes even when every worker is busy: a chunk that calls run_chunks itself (nested loops), or
// several threads calling at once, never wait on each other for a free worker. The first exception a
// chunk throws is rethrown to the caller after the other chunks have finished.
//
// Why not std::async or OpenMP: std::async starts a thread per call (what this replaces), and
// OpenMP's runtime would be a second thread pool beside FFTW's and a build dependency for a
// loop this small.
#include <functional>

namespace glarelab {

void run_chunks(int chunks, const std::function<void(int chunk)>& run_chunk);

// The chunks of a caller run on workers at the caller's niceness (one pool per niceness, each
// started by its first caller): a thread working below another's priority does not lend its
// chunks to threads at the higher one.
// Workers the calling thread's pool has started so far (they start on demand, up to kMaxChunkWorkers).
int chunk_workers_started();
// The niceness of the calling thread (Linux; 0 elsewhere): what its chunks' workers run at.
int chunk_thread_niceness();
inline constexpr int kMaxChunkWorkers = 15;

}  // namespace glarelab
