#include "data/ping_pong_replay.h"

#include <stdexcept>
#include <string>

namespace dslam {

int PingPongFrame(int i, int n) {
  if (n < 2 || i < 0)
    throw std::invalid_argument("a forwards-and-backwards replay needs 2 frames or more and a step >= 0 (n = " +
                                std::to_string(n) + ", step " + std::to_string(i) + ")");
  const int cycle = 2 * (n - 1);
  const int phase = i % cycle;
  return phase < n ? phase : cycle - phase;
}

void ToPingPongStep(int i, int n, int64_t period_ns,
                    const std::function<std::optional<OdometryMeasurement>(int)>& odometry_into, ImageFrame* f) {
  const int k = PingPongFrame(i, n);
  const bool forwards = i % (2 * (n - 1)) < n;
  f->frame_index = i;
  f->t_ns = static_cast<int64_t>(i) * period_ns;
  // Backwards (and turning at frame 0), the step from recorded frame k+1 (1) to k undoes the recorded
  // increment into k+1 (1).
  const int undone = forwards ? (k == 0 ? 1 : -1) : k + 1;
  if (i == 0) {
    f->odometry.reset();
  } else if (undone < 0) {
    f->odometry = odometry_into(k);
  } else {
    f->odometry = odometry_into(undone);
    if (f->odometry) f->odometry->T_prev_curr = f->odometry->T_prev_curr.inverse();
  }
  if (!(forwards && k < n - 1)) f->flow_to_next.release();
}

}  // namespace dslam
