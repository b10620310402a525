#pragma once
// FFTW float wisdom kept in a file between runs, so that the planned float32 path's transforms can
// be FFTW_MEASURE plans (the fastest FFTW finds, faster than FFTW_ESTIMATE's: docs/PERFORMANCE.md,
// "Measurements behind the code's choices") and still be the same plans, with the same
// rounding and so the same bits, in every run on a machine.
//
// Why a file: FFTW_MEASURE times candidate plans, so two runs that each measured could pick
// different plans and give frames that differ in their last bits (a live run and a prepared run of
// one session, compared bit for bit, would not be the same). The first plan of a problem on a
// machine is measured and written to the file; every later plan of that problem, in this process or
// another, is read from it (FFTW reuses wisdom of a problem rather than measuring it again). Planning
// takes an exclusive lock on a lock file beside the wisdom (flock), held from reading the wisdom to
// writing it back, so two processes that plan the same new problem at once get the one plan the
// first measured. The wisdom is written to a temporary file and renamed over the old one: a crash
// leaves the old file or the new one, never half of one.
//
// Where: GLARELAB_FFTW_WISDOM if set (a file path; "none" keeps no file), else
// $XDG_CACHE_HOME/glarelab/fftwf-<host>.wisdom, else ~/.cache/glarelab/fftwf-<host>.wisdom. The host
// is in the name because wisdom holds plans for one processor; a home directory shared by a lab's
// machines keeps one file per machine. Where no file can be kept, kept plans are FFTW_ESTIMATE
// plans (chosen from the sizes alone, so the same in every run too) and describe() says why.
#include <functional>
#include <string>

struct fftwf_plan_s;

namespace glarelab {

struct FftwWisdomPlace {
  std::string path;    // the wisdom file; empty: none is kept
  std::string reason;  // why none is kept (empty when one is)
  bool kept() const { return !path.empty(); }
  // One line for logs and reports: "measured once and kept in PATH" or "estimated (REASON)".
  std::string describe() const;
};

// The place for this process: decided from the environment on first use, or the last
// use_fftw_wisdom_file().
FftwWisdomPlace fftw_wisdom_place();
// From now on, this process keeps its wisdom in `path` ("" or "none": keeps none; plans are estimated).
// The directory is created if need be; a directory that cannot be made gives a place with none kept
// and the reason.
void use_fftw_wisdom_file(const std::string& path);

// A measured plan, make_plan(FFTW_MEASURE), with the kept wisdom: the file is read under the lock,
// the plan made, and the wisdom written back if planning added to it. Without a place, or where the
// lock cannot be taken, make_plan(FFTW_ESTIMATE). The caller holds fftw_planner_mutex(); make_plan
// adds its own flags (FFTW_PRESERVE_INPUT, ...) to the ones it is given, and may be called more than
// once: again with FFTW_WISDOM_ONLY to check that the wisdom holds the plan, and with FFTW_ESTIMATE
// where it does not.
fftwf_plan_s* plan_with_kept_wisdom(const std::function<fftwf_plan_s*(unsigned rigor_flags)>& make_plan);

}  // namespace glarelab
