// URDF loading: parse with urdfdom (its messages captured from console_bridge), check the whole
// model and every name against the graph, then add links, joints and floating edges. Every
// check that can fail runs before the first add, so a rejected load creates nothing.
// Contract: urdf.h.
#include "semgraph/models/urdf.h"

#include <console_bridge/console.h>
#include <urdf_model/model.h>
#include <urdf_parser/urdf_parser.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

#include "semgraph/semantics/describe.h"
#include "semgraph/semantics/names.h"

namespace semgraph::models {

using base::ErrorCode;
using base::Unexpected;
using core::BuildError;

namespace {

// Collects urdfdom's messages (errors and warnings) while it parses.
class CapturedMessages : public console_bridge::OutputHandler {
 public:
  CapturedMessages() { console_bridge::useOutputHandler(this); }
  ~CapturedMessages() override { console_bridge::restorePreviousOutputHandler(); }
  CapturedMessages(const CapturedMessages&) = delete;
  CapturedMessages& operator=(const CapturedMessages&) = delete;
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level < console_bridge::CONSOLE_BRIDGE_LOG_WARN) return;
    if (!text_.empty()) text_ += "; ";
    text_ += text;
  }
  [[nodiscard]] const std::string& text() const noexcept { return text_; }

 private:
  std::string text_;
};

BuildError Error(ErrorCode code, const std::string& what, const std::string& reason) {
  return BuildError{code,
                    what + " rejected (" + std::string(base::ToString(code)) + "): " + reason};
}

std::string Num(double x) {
  std::ostringstream s;
  s.precision(9);
  s << x;
  return s.str();
}

struct PlannedJoint {
  const urdf::Joint* urdf = nullptr;
  std::string name, parent, child, mimic;  // prefixed
  core::JointType type = core::JointType::kFixed;
  bool floating = false;
};

template <coord::Backend B>
base::Expected<Robot, BuildError> Load(core::SceneGraph<B>& g, const std::string& xml,
                                       const std::string& what, std::string_view prefix_view) {
  const std::string prefix(prefix_view);
  urdf::ModelInterfaceSharedPtr model;
  {
    CapturedMessages messages;
    model = urdf::parseURDF(xml);
    if (!model) {
      return Unexpected{
          Error(ErrorCode::kInvalidModel, what,
                "urdfdom could not parse it" +
                    (messages.text().empty() ? std::string() : ": " + messages.text()))};
    }
  }
  const auto invalid = [&](const std::string& reason) {
    return Unexpected{Error(ErrorCode::kInvalidModel, what, reason)};
  };
  if (!model->getRoot()) return invalid("the model has no root link");

  // Depth-first order from the root (child joints come sorted by name from urdfdom).
  Robot robot;
  robot.name = model->getName();
  robot.prefix = prefix;
  std::vector<const urdf::Link*> links;
  std::vector<const urdf::Joint*> joints;
  {
    std::vector<const urdf::Link*> stack{model->getRoot().get()};
    while (!stack.empty()) {
      const urdf::Link* l = stack.back();
      stack.pop_back();
      links.push_back(l);
      // Push children in reverse so that the first child joint is visited first.
      for (auto it = l->child_joints.rbegin(); it != l->child_joints.rend(); ++it) {
        const urdf::Joint* j = it->get();
        const auto child = model->links_.find(j->child_link_name);
        if (child == model->links_.end())
          return invalid("joint " + j->name + " has no child link " + j->child_link_name);
        stack.push_back(child->second.get());
      }
    }
    if (links.size() != model->links_.size())
      return invalid("not every link is reachable from the root link");
    // Joints in the order their child links were visited.
    for (std::size_t i = 1; i < links.size(); ++i) {
      const urdf::JointSharedPtr& pj = links[i]->parent_joint;
      if (!pj) return invalid("link " + links[i]->name + " has no parent joint");
      joints.push_back(pj.get());
    }
  }

  // Names: every prefixed name must be valid.
  const auto check_name = [&](const std::string& kind,
                              const std::string& n) -> std::optional<BuildError> {
    if (auto ok = semantics::ValidateName(n); !ok) {
      return Error(ErrorCode::kInvalidModel, what,
                   kind + " name: " + semantics::Describe(ok.error(), n));
    }
    return std::nullopt;
  };
  for (const urdf::Link* l : links) {
    robot.links.push_back(prefix + l->name);
    if (auto e = check_name("link", robot.links.back())) return Unexpected{*e};
  }
  robot.root = robot.links.front();

  // Joints: types, numbers, axes, limits, mimics.
  std::vector<PlannedJoint> planned;
  std::unordered_map<std::string, const urdf::Joint*> by_name;
  for (const urdf::Joint* j : joints) by_name.emplace(j->name, j);
  for (const urdf::Joint* j : joints) {
    PlannedJoint p;
    p.urdf = j;
    p.name = prefix + j->name;
    p.parent = prefix + j->parent_link_name;
    p.child = prefix + j->child_link_name;
    const std::string jw = "joint " + j->name + ": ";
    switch (j->type) {
      case urdf::Joint::REVOLUTE:
        p.type = core::JointType::kRevolute;
        break;
      case urdf::Joint::CONTINUOUS:
        p.type = core::JointType::kContinuous;
        break;
      case urdf::Joint::PRISMATIC:
        p.type = core::JointType::kPrismatic;
        break;
      case urdf::Joint::FIXED:
        p.type = core::JointType::kFixed;
        break;
      case urdf::Joint::FLOATING:
        p.floating = true;
        break;
      case urdf::Joint::PLANAR:
        return invalid(jw + "planar joints are not supported");
      default:
        return invalid(jw + "the joint type is unknown (not supported)");
    }
    if (!p.floating) {
      if (auto e = check_name("joint", p.name)) return Unexpected{*e};
    }
    if (j->parent_link_name == j->child_link_name)
      return invalid(jw + "its parent and child are the same link");
    const urdf::Pose& o = j->parent_to_joint_origin_transform;
    const double numbers[] = {o.position.x, o.position.y, o.position.z, o.rotation.x, o.rotation.y,
                              o.rotation.z, o.rotation.w, j->axis.x,    j->axis.y,    j->axis.z};
    for (double x : numbers) {
      if (!std::isfinite(x)) return invalid(jw + "a number of its origin or axis is not finite");
    }
    const bool movable = p.type != core::JointType::kFixed && !p.floating;
    if (movable &&
        std::sqrt(j->axis.x * j->axis.x + j->axis.y * j->axis.y + j->axis.z * j->axis.z) < 1e-12) {
      return invalid(jw + "its axis has no direction");
    }
    if (p.type == core::JointType::kRevolute || p.type == core::JointType::kPrismatic) {
      if (!j->limits)
        return invalid(jw + "a " + std::string(core::ToString(p.type)) + " joint needs <limit>");
      if (!std::isfinite(j->limits->lower) || !std::isfinite(j->limits->upper)) {
        return invalid(jw + "its limits are not finite");
      }
      if (!(j->limits->lower <= j->limits->upper)) {
        return invalid(jw + "the lower limit " + Num(j->limits->lower) +
                       " is above the upper limit " + Num(j->limits->upper));
      }
    }
    if (j->mimic) {
      const auto m = by_name.find(j->mimic->joint_name);
      if (!movable) return invalid(jw + "only a movable joint can mimic another");
      if (!std::isfinite(j->mimic->multiplier) || !std::isfinite(j->mimic->offset)) {
        return invalid(jw + "its mimic multiplier or offset is not finite");
      }
      if (m == by_name.end())
        return invalid(jw + "it mimics joint " + j->mimic->joint_name + ", which does not exist");
      const urdf::Joint* mj = m->second;
      if (mj->type == urdf::Joint::FIXED || mj->type == urdf::Joint::FLOATING) {
        return invalid(jw + "it mimics joint " + mj->name + ", which is not a movable joint");
      }
      if (mj->mimic)
        return invalid(jw + "it mimics joint " + mj->name + ", which itself is a mimic joint");
      if (mj == j) return invalid(jw + "it mimics itself");
      p.mimic = prefix + mj->name;
    }
    planned.push_back(std::move(p));
  }

  // Clashes with the graph: duplicate_joint -> duplicate_body -> duplicate_frame.
  for (const PlannedJoint& p : planned) {
    if (!p.floating && g.FindJoint(p.name)) {
      return Unexpected{
          Error(ErrorCode::kDuplicateJoint, what, "a joint named " + p.name + " already exists")};
    }
  }
  for (const std::string& l : robot.links) {
    if (g.FindBody(l).is_valid()) {
      return Unexpected{
          Error(ErrorCode::kDuplicateBody, what, "body " + l + " (a link) already exists")};
    }
  }
  for (const std::string& l : robot.links) {
    if (g.FindFrame(l).is_valid()) {
      return Unexpected{
          Error(ErrorCode::kDuplicateFrame, what, "frame " + l + " (a link frame) already exists")};
    }
  }

  // Apply. Everything that can fail was checked above; an add failing now is a bug, reported.
  const auto apply = [&](const core::BuildResult& r) -> std::optional<BuildError> {
    if (r) return std::nullopt;
    return r.error();
  };
  for (const std::string& l : robot.links) {
    if (auto e = apply(g.AddBody(l))) return Unexpected{*e};
    if (auto e = apply(g.AddFrame(l, l))) return Unexpected{*e};
  }
  for (int pass = 0; pass < 2; ++pass) {  // masters before mimics
    for (const PlannedJoint& p : planned) {
      if ((pass == 0) != p.mimic.empty()) continue;
      if (p.floating) {
        if (auto e = apply(g.AddPose(core::PoseSpec::Of(p.child).RelativeTo(p.parent),
                                     Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero()))) {
          return Unexpected{*e};
        }
        if (auto e = apply(
                g.AddTwist(core::TwistSpec::Of(p.child).RelativeTo(p.parent).ExpressedIn(p.child),
                           Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()))) {
          return Unexpected{*e};
        }
        robot.floating_joints.push_back(p.child + " wrt " + p.parent);
        continue;
      }
      const urdf::Joint* j = p.urdf;
      core::JointSpec s;
      s.name = p.name;
      s.type = p.type;
      s.parent = p.parent;
      s.child = p.child;
      const urdf::Pose& o = j->parent_to_joint_origin_transform;
      s.q_origin =
          Eigen::Quaterniond(o.rotation.w, o.rotation.x, o.rotation.y, o.rotation.z).normalized();
      s.p_origin = Eigen::Vector3d(o.position.x, o.position.y, o.position.z);
      s.axis = Eigen::Vector3d(j->axis.x, j->axis.y, j->axis.z);
      if (j->limits &&
          (p.type == core::JointType::kRevolute || p.type == core::JointType::kPrismatic)) {
        s.lower = j->limits->lower;
        s.upper = j->limits->upper;
      }
      if (!p.mimic.empty()) {
        s.mimic = p.mimic;
        s.multiplier = j->mimic->multiplier;
        s.offset = j->mimic->offset;
      }
      if (auto e = apply(g.AddJoint(s))) return Unexpected{*e};
    }
  }
  for (const PlannedJoint& p : planned) {
    if (p.floating) continue;
    if (!p.mimic.empty()) {
      robot.mimic_joints.push_back(p.name);
    } else if (p.type == core::JointType::kFixed) {
      robot.fixed_joints.push_back(p.name);
    } else {
      robot.joints.push_back(p.name);
    }
  }
  std::vector<std::string_view> names(robot.joints.begin(), robot.joints.end());
  auto group = g.MakeJointGroup(names);
  if (!group) return Unexpected{group.error()};
  robot.group = std::move(*group);
  return robot;
}

}  // namespace

template <coord::Backend B>
base::Expected<Robot, BuildError> LoadUrdfFile(core::SceneGraph<B>& graph, std::string_view file,
                                               std::string_view prefix) {
  const std::string what = "robot model " + std::string(file);
  std::string path(file);
  if (path.rfind("package://", 0) == 0) {
    return Unexpected{
        Error(ErrorCode::kInvalidModel, what,
              "package:// URIs are not resolved (no ROS package paths); give a file path")};
  }
  if (path.rfind("file://", 0) == 0) path = path.substr(7);
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    return Unexpected{Error(ErrorCode::kInvalidModel, what,
                            "cannot read the file: " + std::string(std::strerror(errno)))};
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) return Unexpected{Error(ErrorCode::kInvalidModel, what, "cannot read the file")};
  return Load(graph, text.str(), what, prefix);
}

template <coord::Backend B>
base::Expected<Robot, BuildError> LoadUrdfString(core::SceneGraph<B>& graph, std::string_view xml,
                                                 std::string_view prefix) {
  return Load(graph, std::string(xml), "robot model", prefix);
}

template base::Expected<Robot, BuildError> LoadUrdfFile(core::SceneGraph<coord::QuaternionBackend>&,
                                                        std::string_view, std::string_view);
template base::Expected<Robot, BuildError> LoadUrdfFile(
    core::SceneGraph<coord::HomogeneousBackend>&, std::string_view, std::string_view);
template base::Expected<Robot, BuildError> LoadUrdfString(
    core::SceneGraph<coord::QuaternionBackend>&, std::string_view, std::string_view);
template base::Expected<Robot, BuildError> LoadUrdfString(
    core::SceneGraph<coord::HomogeneousBackend>&, std::string_view, std::string_view);

}  // namespace semgraph::models
