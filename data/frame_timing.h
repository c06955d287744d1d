#pragma once
// When one frame passed each stage of an online pipeline, carried with the frame from its first input to
// its published estimate, so that the latency budget is measured per stage (pipeline/stage_latency.h).
// Times are steady-clock nanoseconds (SteadyClockNs); 0 = not recorded. The frame's capture stamp is
// its t_ns (the sensor's clock), carried beside it.

#include <chrono>
#include <cstdint>

namespace dslam {

// Seconds of the steady clock since `start` (a stage's or a run's duration).
inline double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

inline int64_t SteadyClockNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

struct FrameTiming {
  int64_t received_ns = 0;   // its first part arrived (serve) or its reading began (run)
  double decode_ms = 0.0;    // decoding its parts (within received -> assembled)
  int64_t assembled_ns = 0;  // whole and decoded (and masked): handed to the pipeline
  int64_t frontend_start_ns = 0, frontend_end_ns = 0;
  int64_t backend_start_ns = 0, backend_end_ns = 0;
  int64_t published_ns = 0;  // its estimate written (serve) or handed on (run)
};

}  // namespace dslam
