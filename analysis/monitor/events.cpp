#include "analysis/monitor/events.hpp"

#include <algorithm>
#include <cmath>

namespace dynid {

TruthScore scoreEvents(const std::vector<std::pair<double, double>>& episodes,
                       const std::vector<MonitorEvent>& events) {
  TruthScore out;
  out.episodes = static_cast<int>(episodes.size());
  for (const auto& episode : episodes) {
    // (Not a structured binding: clang 14 cannot capture one in a lambda.)
    const double start = episode.first, end = episode.second;
    const auto hit = std::find_if(events.begin(), events.end(), [&](const MonitorEvent& e) {
      return e.start >= start && e.start <= end + out.window;
    });
    if (hit != events.end() && hit->start <= start + out.window) {
      ++out.detected;
      out.delays.push_back(hit->start - start);
    } else {
      out.missed_starts.push_back(start);
    }
  }
  for (const MonitorEvent& e : events) {
    const bool explained = std::any_of(episodes.begin(), episodes.end(), [&](const auto& ep) {
      return e.end >= ep.first && e.start <= ep.second + out.window;
    });
    if (!explained) ++out.false_alarms;
  }
  return out;
}

}  // namespace dynid
