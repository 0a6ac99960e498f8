// File: semgraph/dds/publisher.h
//
// Publisher: shares one process's scene graph over DDS (docs/distributed.md). It owns every
// body, frame, pose edge and twist edge of its graph and publishes
//   - the structure: the whole set of elements, one sample per owner on the structure topic
//     (reliable, transient-local, keep-last 1: a late mirror receives the latest structure),
//     re-sent by PublishStructure() after adds and removals (a removal is an element that is no
//     longer in the set);
//   - values: one sample per edge update on the value topic (reliable, transient-local,
//     keep-last 1 per edge), numbered per edge so that mirrors drop repeats and reorders;
//   - stamped samples (the time feature, docs/time.md): a stamped edge (one with a history:
//     made by a stamped add before PublishStructure) is announced stamped, with the graph's
//     time options, and each stamped SetPose/SetTwist goes out on the sample topic with its
//     stamp (the graph's time; the publisher's clock stays in stamp_ns for monitors); mirrors
//     insert the samples into the replica's histories, whose rules (out of order, duplicate
//     stamps, window) decide reorders and repeats; each sample carries its covariance (zero:
//     exact), and the structure carries a stamped edge's newest sample with its covariance;
//   - joints (core/joints.h): each live joint with its AddJoint data (type, parent and child
//     frames, origin, axis, limits, mimic) and state, in place of its two edges; joint states
//     set through this Publisher (SetJoints, SetJointPositions, SetJointState,
//     SetJointAccelerations, stamped or not) go out per joint (q, qdot; on the sample topic when
//     stamped), mimics follow on mirrors;
//   - accelerations (docs/dynamics.md): a timeless twist edge's value carries the acceleration
//     the graph stores on it (edge form) or says it has none, so a twist set without one clears
//     the mirrors' as it clears the graph's; a stamped twist sample carries the acceleration its
//     history stores at its stamp, or none; a joint's state (stamped or not) carries its qddot
//     once it was given. The structure carries them as well (stamped: the newest sample's);
//   - wrenches (core/wrenches.h): each stored (on, by) pair with its storage frame is a
//     structure element (AddWrench / RemoveWrench on the graph, then PublishStructure), and
//     SetWrench through this Publisher sends the new (f_S, m_So_S) on the value topic; a stamped
//     pair is announced stamped (newest sample and stamp), its samples go on the sample topic.
// Each Publisher is one incarnation: a random 64-bit source id and its start time; a restarted
// process is a new incarnation of the same owner name and mirrors reconcile to it.
//
// Only the quaternion backend (SceneGraph<>) is shared; edges go on the wire in edge form
// (pose: X_TH of {tail} -> {head} in [tail]; twist: the screw twist at {head} in [head]).
// Costs: PublishStructure O(frames + edges) and one DDS sample (allocates); SetPose/SetTwist
// O(1) for the graph plus one DDS write of a value sample (about 270 bytes, 168 of them the
// covariance, plus 49 for the acceleration's flag and numbers; the DDS write takes Cyclone's
// locks and allocates its serialized sample: it is not on the real-time path); SetWrench and
// SetAcceleration likewise; in a batch (BeginBatch / Flush) a copy into the preallocated batch,
// and one DDS write per Flush.
// Thread safety: one thread uses a Publisher and its graph (the graph's own rules apply to
// readers of compiled queries on other threads).
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "semgraph/core/scene_graph.h"
#include "semgraph/dds/export.h"

namespace semgraph::dds {

/// DDS's default domain (the id of the CYCLONEDDS_URI configuration, else 0).
inline constexpr std::uint32_t kDefaultDomain = 0xFFFFFFFFu;

/// The clock of value stamps (DDS's time: nanoseconds since the Unix epoch).
[[nodiscard]] SEMGRAPH_DDS_EXPORT std::int64_t NowNs() noexcept;

struct PublisherOptions {
  std::string owner;  ///< a valid name, unique among publishers of a domain
  std::uint32_t domain = kDefaultDomain;
};

class SEMGRAPH_DDS_EXPORT Publisher {
 public:
  /// Joins the domain and creates the writers. Fails (message) when the owner name is not a
  /// valid name or DDS refuses. The graph must outlive the publisher and must not move.
  static base::Expected<std::unique_ptr<Publisher>, std::string> Create(core::SceneGraph<>& graph,
                                                                        PublisherOptions options);
  ~Publisher();
  Publisher(const Publisher&) = delete;
  Publisher& operator=(const Publisher&) = delete;

  /// Publishes the graph's whole structure with every edge's current value (call it after the
  /// graph's adds and removals). Build time: allocates.
  [[nodiscard]] base::Expected<base::Ok, std::string> PublishStructure();

  /// Sets the value in the graph (SceneGraph::SetPose, same codes), then publishes it when
  /// the graph accepted it. A failed DDS write does not change the code (the graph holds the
  /// value); it is counted in write_failures().
  [[nodiscard]] base::ErrorCode SetPose(core::PoseHandle edge, const Eigen::Quaterniond& q_TH,
                                        const Eigen::Vector3d& p_ToHo_T) noexcept;
  [[nodiscard]] base::ErrorCode SetTwist(core::TwistHandle edge, const Eigen::Vector3d& v_DHo_H,
                                         const Eigen::Vector3d& w_DH_H) noexcept;
  /// With a covariance (docs/uncertainty.md): SceneGraph's SetPose/SetTwist with a covariance
  /// (same codes: kInvalidNumber, kInvalidCovariance for a bad one), then the value goes out
  /// with the covariance as the graph stored it (edge form, linear first, symmetrized; on the
  /// wire packed as 21 numbers) and mirrors set both. A value without one (the calls above, or
  /// a null matrix) is exact: it goes out with a zero covariance, and mirrors set it to zero.
  [[nodiscard]] base::ErrorCode SetPose(core::PoseHandle edge, const Eigen::Quaterniond& q_TH,
                                        const Eigen::Vector3d& p_ToHo_T,
                                        const core::CovarianceInput& covariance) noexcept;
  [[nodiscard]] base::ErrorCode SetTwist(core::TwistHandle edge, const Eigen::Vector3d& v_DHo_H,
                                         const Eigen::Vector3d& w_DH_H,
                                         const core::CovarianceInput& covariance) noexcept;
  /// A stamped sample: SceneGraph's stamped SetPose/SetTwist (same codes; the edge must be
  /// stamped), then the sample as the history stores it is published with its stamp.
  [[nodiscard]] base::ErrorCode SetPose(core::PoseHandle edge, const Eigen::Quaterniond& q_TH,
                                        const Eigen::Vector3d& p_ToHo_T,
                                        core::Stamp stamp) noexcept;
  [[nodiscard]] base::ErrorCode SetTwist(core::TwistHandle edge, const Eigen::Vector3d& v_DHo_H,
                                         const Eigen::Vector3d& w_DH_H, core::Stamp stamp) noexcept;
  /// A stamped sample with a covariance: SceneGraph's stamped SetPose/SetTwist with a
  /// covariance (same codes), then the sample goes out as its history stores it, with the
  /// covariance stored for that stamp (edge form, packed as above); mirrors insert both into
  /// their history, which interpolates covariances between samples as the publisher's does. A
  /// stamped sample without one (the calls above) goes out with a zero covariance: exact.
  [[nodiscard]] base::ErrorCode SetPose(core::PoseHandle edge, const Eigen::Quaterniond& q_TH,
                                        const Eigen::Vector3d& p_ToHo_T, core::Stamp stamp,
                                        const core::CovarianceInput& covariance) noexcept;
  [[nodiscard]] base::ErrorCode SetTwist(core::TwistHandle edge, const Eigen::Vector3d& v_DHo_H,
                                         const Eigen::Vector3d& w_DH_H, core::Stamp stamp,
                                         const core::CovarianceInput& covariance) noexcept;

  /// Accelerations (docs/dynamics.md). SetTwist with an acceleration in the edge form (a_DHo_H,
  /// alpha_DH_H: at {head}, in [head]): SceneGraph's SetTwist then SetAcceleration, published as
  /// one value. The acceleration is checked first: kInvalidNumber leaves the twist unchanged;
  /// SetAcceleration's other codes (kJointEdge, kStampMismatch) leave the twist set and
  /// published without an acceleration. SetAcceleration alone: SceneGraph's (same codes), then
  /// the edge's twist value goes out again with it. Timeless twist edges only.
  [[nodiscard]] base::ErrorCode SetTwist(core::TwistHandle edge, const Eigen::Vector3d& v_DHo_H,
                                         const Eigen::Vector3d& w_DH_H,
                                         const core::AccelerationInput& acceleration) noexcept;
  [[nodiscard]] base::ErrorCode SetAcceleration(core::TwistHandle edge,
                                                const Eigen::Vector3d& a_DHo_H,
                                                const Eigen::Vector3d& alpha_DH_H) noexcept;
  /// Stamped accelerations (docs/dynamics.md "Stamped accelerations"), stamped twist edges:
  /// SetTwist at a stamp with the sample's acceleration (edge form; checked first as above,
  /// then SceneGraph's stamped SetTwist and SetAcceleration), published as one sample with it.
  /// SetAcceleration at a stamp: SceneGraph's (the twist sample at `stamp` must exist, same
  /// codes), then that sample goes out again with its acceleration. A stamped sample set
  /// without one goes out without one (none: never the previous sample's).
  [[nodiscard]] base::ErrorCode SetTwist(core::TwistHandle edge, const Eigen::Vector3d& v_DHo_H,
                                         const Eigen::Vector3d& w_DH_H, core::Stamp stamp,
                                         const core::AccelerationInput& acceleration) noexcept;
  [[nodiscard]] base::ErrorCode SetAcceleration(core::TwistHandle edge,
                                                const Eigen::Vector3d& a_DHo_H,
                                                const Eigen::Vector3d& alpha_DH_H,
                                                core::Stamp stamp) noexcept;
  /// A wrench's new value (SceneGraph::SetWrench, same codes): (f_S, m_So_S) in the handle's
  /// storage frame, published on the value topic when the graph took it. The pair itself is
  /// structure: add and remove it on the graph, then PublishStructure().
  [[nodiscard]] base::ErrorCode SetWrench(core::WrenchHandle wrench, const Eigen::Vector3d& f_S,
                                          const Eigen::Vector3d& m_So_S) noexcept;
  /// A stamped wrench's sample (SceneGraph's stamped SetWrench, same codes: the pair must be
  /// stamped, i.e. added with a stamp), published on the sample topic with its stamp as its
  /// history stores it. A stamped pair goes in the structure with its newest sample and stamp.
  [[nodiscard]] base::ErrorCode SetWrench(core::WrenchHandle wrench, const Eigen::Vector3d& f_S,
                                          const Eigen::Vector3d& m_So_S,
                                          core::Stamp stamp) noexcept;

  /// Joint states (SceneGraph's calls of the same names, same codes and messages), then each
  /// joint given is published with its state (mimics follow on the mirrors). A stamped
  /// SetJoints that makes a joint stamped (its first stamped state) republishes the structure.
  core::BuildResult SetJoints(std::span<const core::JointValue> positions,
                              std::span<const core::JointValue> velocities);
  core::BuildResult SetJoints(std::span<const core::JointValue> positions,
                              std::span<const core::JointValue> velocities, core::Stamp stamp);
  /// With accelerations qddot (timeless joints): each joint named goes out with the state the
  /// graph holds after the call (q, qdot, qddot).
  core::BuildResult SetJoints(std::span<const core::JointValue> positions,
                              std::span<const core::JointValue> velocities,
                              std::span<const core::JointValue> accelerations);
  /// Stamped, with accelerations (docs/dynamics.md "Stamped accelerations"): SceneGraph's
  /// stamped SetJoints with qddot, then each joint named goes out as the stamped one above,
  /// with the joint's qddot (stamped states of a joint that has one always carry it).
  core::BuildResult SetJoints(std::span<const core::JointValue> positions,
                              std::span<const core::JointValue> velocities,
                              std::span<const core::JointValue> accelerations, core::Stamp stamp);
  [[nodiscard]] base::ErrorCode SetJointAccelerations(const core::JointGroup& group,
                                                      std::span<const double> qddot) noexcept;
  [[nodiscard]] base::ErrorCode SetJointState(const core::JointGroup& group,
                                              std::span<const double> q,
                                              std::span<const double> qdot,
                                              std::span<const double> qddot) noexcept;
  [[nodiscard]] base::ErrorCode SetJointPositions(const core::JointGroup& group,
                                                  std::span<const double> q) noexcept;
  [[nodiscard]] base::ErrorCode SetJointPositions(const core::JointGroup& group,
                                                  std::span<const double> q,
                                                  core::Stamp stamp) noexcept;
  [[nodiscard]] base::ErrorCode SetJointState(const core::JointGroup& group,
                                              std::span<const double> q,
                                              std::span<const double> qdot) noexcept;
  [[nodiscard]] base::ErrorCode SetJointState(const core::JointGroup& group,
                                              std::span<const double> q,
                                              std::span<const double> qdot,
                                              core::Stamp stamp) noexcept;
  /// Real-time stamped with qddot (SceneGraph's, allocation-free): each joint of the group goes
  /// out as a stamped sample with the qddot given (SetJointAccelerations: with the q and qdot
  /// of the joint's newest sample).
  [[nodiscard]] base::ErrorCode SetJointAccelerations(const core::JointGroup& group,
                                                      std::span<const double> qddot,
                                                      core::Stamp stamp) noexcept;
  [[nodiscard]] base::ErrorCode SetJointState(const core::JointGroup& group,
                                              std::span<const double> q,
                                              std::span<const double> qdot,
                                              std::span<const double> qddot,
                                              core::Stamp stamp) noexcept;

  /// Batching, one DDS write per control cycle: after BeginBatch(), the values set through
  /// this publisher (poses, twists, joint states, stamped or not) are collected (up to 1024,
  /// preallocated; a full batch is written at once) and Flush() writes them as one sample on the
  /// batch topic (reliable, transient-local, keep-last 64 batches per publisher) and ends the
  /// batch. Mirrors apply a batch's values in order, under the same rules as single values.
  /// Flush republishes the structure (allocates) when a new mirror matched since the last one,
  /// so that it gets every edge's latest value, not only those of the batches it receives.
  void BeginBatch() noexcept;
  void Flush();

  /// Waits, at most `timeout`, until each of this publisher's writers has matched at least
  /// `count` mirrors (the writer's side), where the transient-local history gives a later mirror
  /// only the newest values and samples (per edge: the last value, the last 1024 samples). E.g.
  /// before a stream longer than that history. Caveat: a mirror's readers match the writers a
  /// moment after the writers matched them, and a sample written in between reaches that mirror
  /// only through the history: before a stream longer than it, give the mirrors a moment more
  /// (the tests wait 2 s; without it one mirror in three or four missed 800-1,100 of 10,000
  /// samples). Event-driven (the writers' publication-matched status). Fails (message with the
  /// counts) on timeout. Blocks: a set-up step, not for the real-time path.
  base::Expected<base::Ok, std::string> WaitForMirrors(std::uint32_t count,
                                                       std::chrono::milliseconds timeout);

  [[nodiscard]] const std::string& owner() const noexcept;
  [[nodiscard]] std::uint64_t source() const noexcept;
  [[nodiscard]] std::uint64_t revision() const noexcept;
  [[nodiscard]] std::uint64_t write_failures() const noexcept;

 private:
  struct Impl;
  explicit Publisher(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace semgraph::dds
