// ft_sensor_loop: a force/torque sensor on a robot's wrist (examples/ft_sensor_loop.h has the
// scene and its semantics). Each tick of a 1 kHz loop: three joint poses and the sensor's
// reading in through handles, the tool's weight rewritten in its storage frame, and the contact
// wrench on the tool by the environment out, at the tool center point, in the tool's and the
// base's axes, from compiled net-wrench queries. A simulator gives the joints and the reading
// from a known contact; the program exits 1 when the graph's contact differs from it.
//
//   semgraph_ft_sensor_loop [--fast] [TICKS]   (default 1000 ticks paced at 1 kHz; --fast: no
//                                               sleeping, for tests)
#include "ft_sensor_loop.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace ft = semgraph::examples::ft_sensor;

int main(int argc, char** argv) {
  int ticks = 1000;
  bool paced = true;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--fast") == 0) {
      paced = false;
    } else {
      ticks = std::atoi(argv[i]);
    }
  }
  if (ticks <= 0) {
    std::fprintf(stderr, "usage: %s [--fast] [TICKS > 0]\n", argv[0]);
    return 2;
  }

  // ---- Setup: allocations and rich errors are fine here.
  ft::FtSensorLoop loop;
  if (const std::string error = loop.Setup(); !error.empty()) {
    std::fprintf(stderr, "ft_sensor_loop: %s\n", error.c_str());
    return 1;
  }
  std::vector<double> tick_ns(ticks);  // preallocated: the loop allocates nothing

  // ---- The 1 kHz loop.
  const ft::LoopSummary s = ft::RunLoop(loop, ticks, paced, tick_ns);

  std::sort(tick_ns.begin(), tick_ns.end());
  const ft::ContactAtTcp& c = s.last;
  std::printf("ft_sensor_loop: %d ticks at 1 kHz%s, %d failed\n", s.ticks,
              paced ? "" : " (--fast: not paced)", s.failed_ticks);
  std::printf("contact on the tool by the environment, at the tcp, last tick:\n");
  std::printf("  in [tcp]:  f = [%8.4f %8.4f %8.4f] N  m = [%8.4f %8.4f %8.4f] N m\n",
              c.in_tcp.f.x(), c.in_tcp.f.y(), c.in_tcp.f.z(), c.in_tcp.m.x(), c.in_tcp.m.y(),
              c.in_tcp.m.z());
  std::printf("  in [base]: f = [%8.4f %8.4f %8.4f] N  m = [%8.4f %8.4f %8.4f] N m\n",
              c.in_base.f.x(), c.in_base.f.y(), c.in_base.f.z(), c.in_base.m.x(), c.in_base.m.y(),
              c.in_base.m.z());
  std::printf("worst difference from the simulated contact: %.2e\n", s.worst_error);
  std::printf(
      "tick latency (3 SetPose, 2 SetWrench, 3 compiled queries): p50 %.0f ns, "
      "p99 %.0f ns, max %.0f ns\n",
      tick_ns[ticks / 2], tick_ns[ticks * 99 / 100], tick_ns.back());
  return s.failed_ticks == 0 && s.worst_error < 1e-9 ? 0 : 1;
}
