// Which body each tf frame lies on (body_plan.h).
#include "semgraph/ros/body_plan.h"

#include <unordered_set>

namespace semgraph::ros {

std::string_view ToString(StaticMode mode) noexcept {
  return mode == StaticMode::kSameBody ? "same_body" : "own_body";
}

std::optional<StaticMode> StaticModeFromString(std::string_view name) noexcept {
  if (name == "same_body") return StaticMode::kSameBody;
  if (name == "own_body") return StaticMode::kOwnBody;
  return std::nullopt;
}

base::Expected<BodyPlan, std::string> BodyPlan::Make(const LiftOptions& options) {
  BodyPlan plan;
  plan.mode_ = options.static_mode;
  plan.has_map_ = !options.bodies.empty();
  for (const auto& [body, frames] : options.bodies) {
    if (body.empty()) return base::Unexpected(std::string("bodies map: a body with an empty name"));
    for (const std::string& listed : frames) {
      const std::string frame(LiftFrameName(listed));
      if (frame.empty()) {
        return base::Unexpected("bodies map: body " + body + " lists an empty frame name");
      }
      const auto [it, inserted] = plan.listed_.emplace(frame, body);
      if (!inserted && it->second != body) {
        return base::Unexpected("bodies map: frame " + frame + " is listed under bodies " +
                                it->second + " and " + body);
      }
    }
  }
  return plan;
}

void BodyPlan::AddStatic(std::string_view parent, std::string_view child) {
  static_parent_.emplace(std::string(child), std::string(parent));  // the first parent wins
}

std::string_view BodyPlan::StaticParent(std::string_view frame) const {
  const auto it = static_parent_.find(std::string(frame));
  return it == static_parent_.end() ? std::string_view() : std::string_view(it->second);
}

bool BodyPlan::JoinsBodies(std::string_view child) const {
  if (listed_.count(std::string(child)) != 0) return false;  // its body is the map's
  return mode_ == StaticMode::kSameBody || has_map_;
}

std::string BodyPlan::BodyOf(std::string_view frame, const ExistingBody& existing) const {
  std::unordered_set<std::string_view> seen;  // a static loop ends the walk where it closes
  std::string_view f = frame;
  while (true) {
    if (existing) {
      if (std::optional<std::string> body = existing(f)) return *body;
    }
    if (const auto it = listed_.find(std::string(f)); it != listed_.end()) return it->second;
    if (!JoinsBodies(f) || !seen.insert(f).second) return std::string(f);
    const std::string_view parent = StaticParent(f);
    if (parent.empty()) return std::string(f);
    f = parent;
  }
}

}  // namespace semgraph::ros
