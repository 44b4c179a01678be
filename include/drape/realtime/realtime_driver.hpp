#pragma once
/// \file realtime_driver.hpp
/// Real-time pacing: turns wall-clock time into whole fixed time steps, at a constant ratio of
/// simulated to wall time (the real-time factor) whatever the frame rate.
///
/// Each frame the driver measures the wall time \f$ \Delta w \f$ since the previous frame with a
/// monotonic clock, owes the simulation \f$ \rho\,\Delta w \f$ more simulated time (\f$\rho\f$ = real-time
/// factor) and grants \f$ k = \min(\lfloor \text{owed} / \Delta t \rfloor, k_\max) \f$ steps of the fixed
/// `dt`. The remainder (less than one `dt`) carries over to the next frame. When the cap
/// \f$k_\max\f$ bites, the simulated time beyond it is *dropped* (reported, never made up later), so
/// a slow machine runs slower than real time instead of spiralling into ever longer frames.
///
/// The step size never depends on the frame rate and the frame rate is never assumed constant:
/// the same `dt` is used whatever the pacing, so the sequence of states is the same bit for bit
/// (only how many of them fall into each frame changes).
///
/// The owed time is recomputed each frame from exact totals (integer clock ticks since `start()`,
/// steps granted, time dropped), so rounding does not accumulate over a long run.
///
/// The driver does not step anything itself; the caller runs the granted steps of the
/// integrator, which owns dt:
/// \code
///   drape::RealtimeDriver<> driver(integrator.dt(), {/*realtime_factor=*/1.0, /*max_steps_per_frame=*/40});
///   driver.start();
///   while (running) {
///     const auto frame = driver.next_frame();
///     for (int k = 0; k < frame.steps; ++k) integrator.step(state);
///     draw(previous_state, state, frame.interpolation);
///   }
/// \endcode

#include <chrono>
#include <cmath>
#include <cstdint>

#include "drape/core/validation.hpp"

namespace drape {

/// What one frame is granted and how the run is keeping up.
struct RealtimeFrame {
  int steps = 0;                 ///< whole steps of dt to run this frame, in [0, max_steps_per_frame]
  double wall_elapsed = 0.0;     ///< s of wall time since the previous frame (or start())
  double dropped = 0.0;          ///< s of simulated time dropped this frame because of the cap
  double interpolation = 0.0;    ///< owed remainder / dt in [0, 1): where "now" lies between the
                                 ///< last two states (draw (1-a) x_prev + a x_last, lagging one step)
  double achieved_factor = 0.0;  ///< simulated / wall time over this frame (0 if no wall time passed)
  double total_wall = 0.0;       ///< s of wall time since start()
  double total_simulated = 0.0;  ///< s simulated since start() (steps granted x dt)
  double total_dropped = 0.0;    ///< s dropped since start()
  /// Simulated / wall time since start(); equals the requested factor unless the cap dropped time.
  double overall_factor() const { return total_wall > 0 ? total_simulated / total_wall : 0.0; }
};

/// How the driver paces: its settings besides the time step.
struct RealtimeSettings {
  /// Simulated seconds per wall-clock second (0.5 = half speed, 2 = double speed).
  double realtime_factor = 1.0;
  /// Cap on the steps granted per frame; simulated time beyond it is dropped.
  int max_steps_per_frame = 64;

  /// \throws InvalidParameter naming `realtime_factor` (finite and > 0) or `max_steps_per_frame`
  /// ([1, 100000000]).
  void validate() const {
    detail::require_positive_finite("realtime_factor", realtime_factor);
    detail::require_in_range("max_steps_per_frame", max_steps_per_frame, 1, 100'000'000);
  }
};

/// \tparam Clock a monotonic clock with static `now()` (std::chrono::steady_clock by default;
/// tests use a fake clock).
template <class Clock = std::chrono::steady_clock>
class RealtimeDriver {
 public:
  using clock = Clock;
  using time_point = typename Clock::time_point;
  using duration = typename Clock::duration;

  /// \param dt the integrator's fixed time step (s), finite and > 0 (Integrator::dt()).
  /// \throws InvalidParameter naming the parameter and its allowed range.
  explicit RealtimeDriver(double dt, const RealtimeSettings& settings = {})
      : m_dt(dt), m_factor(settings.realtime_factor), m_max_steps(settings.max_steps_per_frame) {
    detail::require_time_step(dt);
    settings.validate();
    m_snap = 0.5 * m_factor * seconds(duration(1));
  }

  /// Starts (or restarts) the clock now: the first frame is measured from here.
  void start() { start(Clock::now()); }
  void start(time_point now) {
    m_start = m_last = now;
    m_steps_total = 0;
    m_dropped_total = 0.0;
    m_started = true;
  }
  bool started() const { return m_started; }

  /// Measures the wall time since the previous frame and grants steps for it. Calls start() first
  /// if it was never called (the first frame then gets no steps).
  RealtimeFrame next_frame() { return next_frame(Clock::now()); }

  /// As next_frame(), at an explicit clock reading (must not go backwards).
  RealtimeFrame next_frame(time_point now) {
    if (!m_started) start(now);
    if (now < m_last) now = m_last;  // a monotonic clock never does this; be safe anyway
    RealtimeFrame f;
    f.wall_elapsed = seconds(now - m_last);
    f.total_wall = seconds(now - m_start);
    // Owed simulated time from exact totals: factor x wall - dropped - granted.
    const double target = m_factor * f.total_wall - m_dropped_total;
    const double owed = target - double(m_steps_total) * m_dt;
    // floor(owed / dt). Owed time within half a clock tick of a whole step counts as that step:
    // the clock cannot resolve finer, and e.g. 0.3 s / 0.001 s = 299.99999999999994 in doubles.
    double whole = std::floor((owed + m_snap) / m_dt);
    if (whole < 0) whole = 0;
    long long steps = static_cast<long long>(whole);
    double remainder = owed - double(steps) * m_dt;
    if (remainder < 0) remainder = 0;
    if (steps > m_max_steps) {
      f.dropped = double(steps - m_max_steps) * m_dt;
      m_dropped_total += f.dropped;
      steps = m_max_steps;
    }
    f.steps = static_cast<int>(steps);
    m_steps_total += steps;
    f.interpolation = remainder / m_dt;
    if (f.interpolation >= 1.0) f.interpolation = std::nextafter(1.0, 0.0);
    f.achieved_factor = f.wall_elapsed > 0 ? double(steps) * m_dt / f.wall_elapsed : 0.0;
    f.total_simulated = double(m_steps_total) * m_dt;
    f.total_dropped = m_dropped_total;
    m_last = now;
    return f;
  }

  double dt() const { return m_dt; }
  double realtime_factor() const { return m_factor; }
  int max_steps_per_frame() const { return m_max_steps; }
  /// Steps granted since start().
  std::int64_t steps_granted() const { return m_steps_total; }

 private:
  static double seconds(duration d) { return std::chrono::duration<double>(d).count(); }

  double m_dt;
  double m_factor;
  int m_max_steps;
  time_point m_start{};
  time_point m_last{};
  std::int64_t m_steps_total = 0;
  double m_dropped_total = 0.0;
  double m_snap = 0.0;  // half a clock tick of simulated time
  bool m_started = false;
};

}  // namespace drape
