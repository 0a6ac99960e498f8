// File: tests/support/kdl_from_urdf.h
//
// A KDL tree built from a urdfdom model, the way ROS's kdl_parser builds it (Debian's
// libkdl-parser-dev would pull in roscpp): one segment per link, named after it, whose joint
// carries the URDF joint's origin and axis in the parent frame, and whose tip is the joint's
// origin. KDL has no mimic joints: a mimic is an ordinary KDL joint whose value the caller sets
// (KdlPositions does: q = multiplier q_master + offset). Test and benchmark helper only.
#pragma once

#include <urdf_model/model.h>
#include <urdf_parser/urdf_parser.h>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>
#include <kdl/tree.hpp>
#include <map>
#include <stdexcept>
#include <string>

namespace semgraph::testing {

inline KDL::Frame ToKdl(const urdf::Pose& p) {
  return KDL::Frame(
      KDL::Rotation::Quaternion(p.rotation.x, p.rotation.y, p.rotation.z, p.rotation.w),
      KDL::Vector(p.position.x, p.position.y, p.position.z));
}

inline KDL::Joint ToKdl(const urdf::Joint& j) {
  const KDL::Frame F_parent_jnt = ToKdl(j.parent_to_joint_origin_transform);
  const KDL::Vector axis(j.axis.x, j.axis.y, j.axis.z);
  switch (j.type) {
    case urdf::Joint::REVOLUTE:
    case urdf::Joint::CONTINUOUS:
      return KDL::Joint(j.name, F_parent_jnt.p, F_parent_jnt.M * (axis / axis.Norm()),
                        KDL::Joint::RotAxis);
    case urdf::Joint::PRISMATIC:
      return KDL::Joint(j.name, F_parent_jnt.p, F_parent_jnt.M * (axis / axis.Norm()),
                        KDL::Joint::TransAxis);
    default:
      return KDL::Joint(j.name, KDL::Joint::None);
  }
}

inline void AddChildren(const urdf::Link& link, KDL::Tree& tree) {
  for (const urdf::LinkSharedPtr& child : link.child_links) {
    const urdf::Joint& j = *child->parent_joint;
    const KDL::Segment segment(child->name, ToKdl(j), ToKdl(j.parent_to_joint_origin_transform));
    if (!tree.addSegment(segment, link.name))
      throw std::runtime_error("KDL refused segment " + child->name);
    AddChildren(*child, tree);
  }
}

/// The KDL tree of a parsed URDF (root segment = the root link's name).
inline KDL::Tree KdlTree(const urdf::ModelInterface& model) {
  KDL::Tree tree(model.getRoot()->name);
  AddChildren(*model.getRoot(), tree);
  return tree;
}

/// KDL joint positions (by the tree's q_nr) from the independent joints' values by name; mimic
/// joints get multiplier * q_master + offset.
inline KDL::JntArray KdlPositions(const urdf::ModelInterface& model, const KDL::Tree& tree,
                                  const std::map<std::string, double>& q, bool velocities = false) {
  KDL::JntArray out(tree.getNrOfJoints());
  for (const auto& [name, element] : tree.getSegments()) {
    const KDL::Joint& joint = element.segment.getJoint();
    if (joint.getType() == KDL::Joint::None) continue;
    const urdf::JointConstSharedPtr j = model.getJoint(joint.getName());
    double value;
    if (j->mimic) {
      value =
          j->mimic->multiplier * q.at(j->mimic->joint_name) + (velocities ? 0.0 : j->mimic->offset);
    } else {
      value = q.at(j->name);
    }
    out(element.q_nr) = value;
  }
  return out;
}

}  // namespace semgraph::testing
