// SceneGraph constraints: every constraint case of the paper's Figs. 2, 4 and 6 (figures
// reconstructed from their captions), one test per error code of docs/rules.md §8, the
// order of the codes when one operation breaks two rules, and the accepted operations around
// them (value updates, removal and re-add, grasps, twist removal).
//
// Every rejection goes through RejectsAndKeeps: the code; phrases of the message, which must
// name the offending frames/bodies and the relation they conflict with; and Dump() equal
// before and after (names, ids, topology, values: docs/rules.md §6 atomicity, including the name
// table, which a rejected add must roll back). Every accepted operation goes through Accepts:
// CheckInvariants() empty afterwards. Semantic rules are the same for every representation, so
// most tests are typed over both backends; the homogeneous backend's own constraints have
// their own suite.
//
// Legend:
//   {x}|X        frame x fixed to body X (point x, orientation frame [x])
//   t -> h       pose edge, stores PoseCoord({h}|H, {t}|T, [t]) = X_TH
//   D ~> {h}     twist edge, stores the screw twist TwistCoord(h|H, D, [h]) = V_DHh_H
//   X_TH         pose of frame h in frame t: rotation R_TH, position p_TH (of h's origin, in [t])
//   V_DCe_R     twist of body C wrt body D at point e in [r]: (v_DCe_R, w_DC_R)
//   Pose(k)      the k-th test value: a distinct proper rotation and position (Dump tells
//                values apart)
#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <ostream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "semgraph/base/error_code.h"
#include "semgraph/core/scene_graph.h"
#include "semgraph/core/scene_graph_debug.h"
#include "support/tolerance.h"

namespace semgraph::semantics {
// Readable ErrorCode in gtest failure messages (found by ADL).
void PrintTo(ErrorCode code, std::ostream* os) { *os << ToString(code); }
}  // namespace semgraph::semantics

namespace semgraph::core {
namespace {

using semgraph::testing::Near;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// ====================================================================== values

/// The k-th test rotation: 0.3 k + 0.1 rad about a fixed tilted axis (never the identity).
Eigen::Quaterniond RotationNumber(int k) {
  return Eigen::Quaterniond(
      Eigen::AngleAxisd(0.3 * k + 0.1, Eigen::Vector3d(1, 2, 3).normalized()));
}
/// The k-th test position.
Eigen::Vector3d PositionNumber(int k) {
  return Eigen::Vector3d(0.5 * k, -0.25 * k, 1.0 + 0.125 * k);
}
/// X_TH of the k-th test value as an isometry, for expected query results.
Eigen::Isometry3d IsometryNumber(int k) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = RotationNumber(k).toRotationMatrix();
  X.translation() = PositionNumber(k);
  return X;
}
/// The k-th test twist (v, w).
Eigen::Vector3d LinearNumber(int k) { return Eigen::Vector3d(0.1 * k, 0.2, -0.3 * k); }
Eigen::Vector3d AngularNumber(int k) { return Eigen::Vector3d(-0.05 * k, 0.1 * k, 0.2); }

// ====================================================================== operations

/// Pose edge {wrt}|wrt_body -> {of}|of_body with X = Pose(k), in edge form.
template <class G>
BuildResult AddEdge(G& graph, std::string_view of, std::string_view of_body, std::string_view wrt,
                    std::string_view wrt_body, int k = 1) {
  return graph.AddPose(PoseSpec::Of(of, of_body).RelativeTo(wrt, wrt_body), RotationNumber(k),
                       PositionNumber(k));
}

/// Twist edge ref_body ~> {point}|body with the k-th twist, as a screw twist.
template <class G>
BuildResult AddScrewTwist(G& graph, std::string_view point, std::string_view body,
                          std::string_view ref_body, int k = 1) {
  return graph.AddTwist(TwistSpec::Of(point, body).RelativeTo(ref_body).ExpressedIn(point),
                        LinearNumber(k), AngularNumber(k));
}

// ====================================================================== assertions

template <class G>
::testing::AssertionResult Accepts(const G& graph, const BuildResult& result) {
  if (!result) return ::testing::AssertionFailure() << "rejected: " << result.error().message;
  if (const std::string broken = CheckInvariants(graph); !broken.empty()) {
    return ::testing::AssertionFailure() << "accepted, but invariants are broken:\n" << broken;
  }
  return ::testing::AssertionSuccess();
}

/// Runs `op` (returning a BuildResult) and checks: rejected with `code`; the message says
/// "rejected (<code>)" and contains every phrase; the graph's Dump() is unchanged; the
/// invariants still hold.
template <class G, class Op>
::testing::AssertionResult RejectsAndKeeps(G& graph, ErrorCode code,
                                           std::initializer_list<std::string_view> phrases,
                                           Op&& op) {
  const std::string before = Dump(graph);
  const BuildResult result = op();
  if (result) {
    return ::testing::AssertionFailure() << "accepted; expected " << base::ToString(code);
  }
  const std::string& message = result.error().message;
  if (result.error().code != code) {
    return ::testing::AssertionFailure()
           << "code " << base::ToString(result.error().code) << ", expected "
           << base::ToString(code) << ": " << message;
  }
  const std::string tag = "rejected (" + std::string(base::ToString(code)) + ")";
  if (message.find(tag) == std::string::npos) {
    return ::testing::AssertionFailure() << "message lacks \"" << tag << "\": " << message;
  }
  for (std::string_view phrase : phrases) {
    if (message.find(phrase) == std::string::npos) {
      return ::testing::AssertionFailure() << "message lacks \"" << phrase << "\": " << message;
    }
  }
  if (const std::string after = Dump(graph); after != before) {
    return ::testing::AssertionFailure() << "the rejection changed the graph.\nbefore:\n"
                                         << before << "after:\n"
                                         << after;
  }
  if (const std::string broken = CheckInvariants(graph); !broken.empty()) {
    return ::testing::AssertionFailure() << "invariants broken after a rejection:\n" << broken;
  }
  return ::testing::AssertionSuccess() << message;
}

/// A query failed with `code`, and Describe() names every phrase.
template <class G, class Result, class Spec>
::testing::AssertionResult QueryFails(const G& graph, const Result& result, const Spec& spec,
                                      ErrorCode code,
                                      std::initializer_list<std::string_view> phrases = {}) {
  if (result)
    return ::testing::AssertionFailure() << "succeeded; expected " << base::ToString(code);
  const std::string text = graph.Describe(result.error(), spec);
  if (result.error().code != code) {
    return ::testing::AssertionFailure() << "code " << base::ToString(result.error().code)
                                         << ", expected " << base::ToString(code) << ": " << text;
  }
  for (std::string_view phrase : phrases) {
    if (text.find(phrase) == std::string::npos) {
      return ::testing::AssertionFailure() << "description lacks \"" << phrase << "\": " << text;
    }
  }
  return ::testing::AssertionSuccess();
}

// ====================================================================== fixtures

// Fig. 2: rigid body nodes containing frame nodes.
//
//    A       B       C       D       E       F
//   {a}     {b}     {c}     {d}     {e}     {f}
template <class G>
void BuildFigure2(G& graph) {
  for (std::string_view body : {"A", "B", "C", "D", "E", "F"})
    ASSERT_TRUE(Accepts(graph, graph.AddBody(body)));
  for (auto [frame, body] :
       {std::pair{"a", "A"}, {"b", "B"}, {"c", "C"}, {"d", "D"}, {"e", "E"}, {"f", "F"}}) {
    ASSERT_TRUE(Accepts(graph, graph.AddFrame(frame, body)));
  }
}

// Fig. 4: pose edges (solid arrows, drawn downward: tail above head).
//
//   {d}|D         {a}|A         {b2}|B        {f}|F
//     |             |             |
//   {c2}|C        {c1}|C        {b1}|B   <- constant: both fixed to B
//
// C is reached from D through c2; linking {d} -> {a} would reach it a second time through c1.
template <class G>
void BuildFigure4(G& graph) {
  ASSERT_TRUE(Accepts(graph, AddEdge(graph, "c2", "C", "d", "D", 1)));
  ASSERT_TRUE(Accepts(graph, AddEdge(graph, "c1", "C", "a", "A", 2)));
  ASSERT_TRUE(Accepts(graph, AddEdge(graph, "b1", "B", "b2", "B", 3)));
  ASSERT_TRUE(Accepts(graph, graph.AddBody("F")));
  ASSERT_TRUE(Accepts(graph, graph.AddFrame("f", "F")));
}

// Fig. 6: pose edges solid, twist edges dotted (~>).
//
//   A ~> {c1}|C        D ~> {c2}|C        F
//          |
//        {c3}|C   (constant: c3 wrt c1, both on C)
//
// The twist of c3's body C wrt A follows from A ~> {c1} and the pose of c3 wrt c1.
template <class G>
void BuildFigure6(G& graph) {
  ASSERT_TRUE(Accepts(graph, AddEdge(graph, "c3", "C", "c1", "C", 1)));
  ASSERT_TRUE(Accepts(graph, AddScrewTwist(graph, "c1", "C", "A", 1)));
  ASSERT_TRUE(Accepts(graph, AddScrewTwist(graph, "c2", "C", "D", 2)));
  ASSERT_TRUE(Accepts(graph, graph.AddBody("F")));
}

// The spray-painting scene of §V (Listing 1 and Fig. 8), pose edges only.
//
//   {b}|B
//    +-- {c}|C
//    |     +-- {o1}|O1
//    |           +-- {f1}|O1   <- Listing 1: constant pose of f1 wrt o1 (added by the test)
//    +-- {e}|E
//          +-- {o2}|O2
template <class G>
void BuildSprayPaintingPoses(G& graph) {
  ASSERT_TRUE(Accepts(graph, AddEdge(graph, "c", "C", "b", "B", 1)));
  ASSERT_TRUE(Accepts(graph, AddEdge(graph, "o1", "O1", "c", "C", 2)));
  ASSERT_TRUE(Accepts(graph, AddEdge(graph, "o2", "O2", "e", "E", 3)));
  ASSERT_TRUE(Accepts(graph, AddEdge(graph, "e", "E", "b", "B", 4)));
}

// Two trees that share no body, and a lone frame, used by the per-code tests.
//
//      {a}|A              {p}|P         {z}|Z  (alone)
//      /    \               |
//  {b}|B   {a2}|A         {q}|Q
//    |
//  {c}|C
//
// Twists: A ~> {b}, P ~> {q}.
template <class G>
void BuildTwoTrees(G& graph) {
  ASSERT_TRUE(Accepts(graph, AddEdge(graph, "b", "B", "a", "A", 1)));
  ASSERT_TRUE(Accepts(graph, AddEdge(graph, "c", "C", "b", "B", 2)));
  ASSERT_TRUE(Accepts(graph, AddEdge(graph, "a2", "A", "a", "A", 3)));
  ASSERT_TRUE(Accepts(graph, AddEdge(graph, "q", "Q", "p", "P", 4)));
  ASSERT_TRUE(Accepts(graph, AddScrewTwist(graph, "b", "B", "A", 1)));
  ASSERT_TRUE(Accepts(graph, AddScrewTwist(graph, "q", "Q", "P", 2)));
  ASSERT_TRUE(Accepts(graph, graph.AddBody("Z")));
  ASSERT_TRUE(Accepts(graph, graph.AddFrame("z", "Z")));
}

// ====================================================================== typed suite

template <class B>
class SceneGraphConstraints : public ::testing::Test {
 protected:
  SceneGraph<B> graph_;
};

struct BackendName {
  template <class B>
  static std::string GetName(int) {
    return B::kName;
  }
};
using Backends = ::testing::Types<coord::QuaternionBackend, coord::HomogeneousBackend>;
TYPED_TEST_SUITE(SceneGraphConstraints, Backends, BackendName);

// ---------------------------------------------------------------------- Fig. 2

TYPED_TEST(SceneGraphConstraints, Figure2AddingBodyEAgainIsRejectedAsDuplicateBody) {
  auto& g = this->graph_;
  BuildFigure2(g);
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kDuplicateBody, {"body E already exists"},
                              [&] { return g.AddBody("E"); }));
}

TYPED_TEST(SceneGraphConstraints, Figure2AddingFramesAAndFAgainIsRejectedAsDuplicateFrame) {
  auto& g = this->graph_;
  BuildFigure2(g);
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kDuplicateFrame, {"frame {a}|A already exists"},
                              [&] { return g.AddFrame("a", "A"); }));
  // Also when the new frame names another body: a frame is one physical entity.
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kDuplicateFrame, {"frame {f}|F already exists"},
                              [&] { return g.AddFrame("f", "B"); }));
}

TYPED_TEST(SceneGraphConstraints, Figure2AddingFrameZWithoutABodyIsRejected) {
  auto& g = this->graph_;
  BuildFigure2(g);
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kFrameWithoutBody, {"{z}", "must name the body"},
                              [&] { return g.AddFrame("z", ""); }));
  EXPECT_TRUE(Accepts(g, g.AddFrame("z", "E")));  // attached to a body, it is fine
}

// ---------------------------------------------------------------------- Fig. 4

TYPED_TEST(SceneGraphConstraints, Figure4ConstantPoseOfB1WrtB2IsAcceptedAndCannotChange) {
  auto& g = this->graph_;
  BuildFigure4(g);  // includes b2 -> b1 with Pose(3)
  EXPECT_TRUE(
      RejectsAndKeeps(g, ErrorCode::kConstantPoseChange,
                      {"pose of {b1}|B wrt {b2}|B", "{b1}|B and {b2}|B are both fixed to body B",
                       "remove the edge first"},
                      [&] { return AddEdge(g, "b1", "B", "b2", "B", 4); }));
  // The same value again is accepted and changes nothing.
  const std::string before = Dump(g);
  EXPECT_TRUE(Accepts(g, AddEdge(g, "b1", "B", "b2", "B", 3)));
  EXPECT_EQ(Dump(g), before);
}

TYPED_TEST(SceneGraphConstraints, Figure4PoseOfC2WrtFIsRejectedBecauseC2HasAPoseParentD) {
  auto& g = this->graph_;
  BuildFigure4(g);
  // The spec's own example message, verbatim.
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kMultiplePoseParents,
                              {"pose of {c2}|C wrt {f}|F rejected (multiple_pose_parents): {c2}|C "
                               "already has a pose parent {d}|D"},
                              [&] { return AddEdge(g, "c2", "C", "f", "F", 5); }));
  // §VI: the inverted relation carries the same information and is accepted.
  EXPECT_TRUE(Accepts(
      g, g.AddPose(PoseSpec::Of("f", "F").RelativeTo("c2", "C"), RotationNumber(5).conjugate(),
                   -(RotationNumber(5).conjugate() * PositionNumber(5)))));
  EXPECT_EQ(g.frame_name(g.pose_parent(g.FindFrame("f"))), "c2");
}

TYPED_TEST(SceneGraphConstraints, Figure4PoseOfAWrtDIsRejectedBecauseCWouldBeReachableTwice) {
  auto& g = this->graph_;
  BuildFigure4(g);
  EXPECT_TRUE(RejectsAndKeeps(
      g, ErrorCode::kDuplicatePosePath,
      {"pose of {a}|A wrt {d}|D", "body C would be reachable twice",
       "from {d}|D: through {d}|D -> {c2}|C", "through the new edge, {d}|D -> {a}|A -> {c1}|C",
       "(such as {c2}|C and {c1}|C)"},
      [&] { return AddEdge(g, "a", "A", "d", "D", 6); }));
}

// ---------------------------------------------------------------------- Fig. 6

TYPED_TEST(SceneGraphConstraints, Figure6TwistOfC2WrtFIsRejectedBecauseC2HasATwistParentD) {
  auto& g = this->graph_;
  BuildFigure6(g);
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kMultipleTwistParents,
                              {"twist of c2|C wrt F", "{c2}|C already has a twist parent: body D"},
                              [&] { return AddScrewTwist(g, "c2", "C", "F", 3); }));
}

TYPED_TEST(SceneGraphConstraints, Figure6TwistOfC3WrtAIsRejectedBecauseItFollowsFromC1) {
  auto& g = this->graph_;
  BuildFigure6(g);
  EXPECT_TRUE(
      RejectsAndKeeps(g, ErrorCode::kDuplicateTwistPath,
                      {"twist of c3|C wrt A", "the twist of C relative to A already follows",
                       "pose tree of {c3}|C"},
                      [&] { return AddScrewTwist(g, "c3", "C", "A", 3); }));
  // It is indeed derivable: the twist of C wrt A at c3, from A ~> {c1} and X_C1C3.
  auto V = g.GetTwist(TwistSpec::Of("c3").RelativeTo("A").ExpressedIn("c3"));
  ASSERT_TRUE(V);
  const Eigen::Isometry3d X_C1C3 = IsometryNumber(1);
  const Eigen::Matrix3d R_C3C1 = X_C1C3.linear().transpose();
  const Eigen::Vector3d w_AC_C1 = AngularNumber(1);
  const Eigen::Vector3d v_A_CC1_C1 = LinearNumber(1);
  const Eigen::Vector3d v_A_CC3_C1 = v_A_CC1_C1 + w_AC_C1.cross(X_C1C3.translation());
  EXPECT_TRUE(Near(V->angular, R_C3C1 * w_AC_C1));
  EXPECT_TRUE(Near(V->linear, R_C3C1 * v_A_CC3_C1));
}

// ---------------------------------------------------------------------- invalid_name

struct BadName {
  std::string name;
  std::string_view phrase;  // what Describe(NameError) says
};
std::vector<BadName> BadNames() {
  return {{"", "name is empty"},
          {std::string(256, 'x'), "256 bytes long (at most 255)"},
          {"ctl\x01name", "byte 3 of the name is a control character"},
          {"del\x7f", "byte 3 of the name is a control character"},
          {"bad\xff"
           "utf8",
           "byte 3 of the name is not valid UTF-8"},
          {"cut\xc3", "byte 3 of the name is not valid UTF-8"}};
}

TYPED_TEST(SceneGraphConstraints,
           InvalidNameRejectsEmptyTooLongControlAndNonUtf8NamesInEveryBuildOperation) {
  auto& g = this->graph_;
  BuildTwoTrees(g);
  for (const BadName& bad : BadNames()) {
    SCOPED_TRACE("name \"" + bad.name + "\"");
    const std::string_view n = bad.name, phrase = bad.phrase;
    const auto rejects = [&](auto op) {
      return RejectsAndKeeps(g, ErrorCode::kInvalidName, {phrase}, op);
    };
    EXPECT_TRUE(rejects([&] { return g.AddBody(n); }));
    EXPECT_TRUE(rejects([&] { return g.AddFrame(n, "A"); }));
    if (!n.empty()) {  // an empty body is frame_without_body
      EXPECT_TRUE(rejects([&] { return g.AddFrame("new", n); }));
    }
    const Eigen::Quaterniond q = RotationNumber(1);
    const Eigen::Vector3d p = PositionNumber(1);
    EXPECT_TRUE(rejects(
        [&] { return g.AddPose(PoseSpec::Of("z", "Z").RelativeTo("c", "C").AtPoint(n), q, p); }));
    EXPECT_TRUE(rejects([&] {
      PoseSpec s = PoseSpec::Of("z", "Z").RelativeTo("c", "C");
      s.orientation = n;
      return g.AddPose(s, q, p);
    }));
    EXPECT_TRUE(rejects([&] {
      return g.AddPose(PoseSpec::Of("z", "Z").RelativeTo("c", "C").RelativeToPoint(n), q, p);
    }));
    EXPECT_TRUE(rejects([&] {
      PoseSpec s = PoseSpec::Of("z", "Z").RelativeTo("c", "C");
      s.ref_orientation = n;
      return g.AddPose(s, q, p);
    }));
    EXPECT_TRUE(rejects([&] {
      return g.AddPose(PoseSpec::Of("z", "Z").RelativeTo("c", "C").ExpressedIn(n), q, p);
    }));
    if (!n.empty()) {  // an empty body is "take it from the frame"
      EXPECT_TRUE(
          rejects([&] { return g.AddPose(PoseSpec::Of("z", n).RelativeTo("c", "C"), q, p); }));
      EXPECT_TRUE(
          rejects([&] { return g.AddPose(PoseSpec::Of("z", "Z").RelativeTo("c", n), q, p); }));
      EXPECT_TRUE(rejects([&] { return AddScrewTwist(g, "z", n, "A"); }));
    }
    EXPECT_TRUE(rejects([&] { return AddScrewTwist(g, n, "Z", "A"); }));
    EXPECT_TRUE(rejects([&] { return AddScrewTwist(g, "z", "Z", n); }));
    EXPECT_TRUE(rejects([&] {
      return g.AddTwist(TwistSpec::Of("z", "Z").RelativeTo("A").ExpressedIn(n), LinearNumber(1),
                        AngularNumber(1));
    }));
    EXPECT_TRUE(rejects([&] { return g.RemovePose(n, "a"); }));
    EXPECT_TRUE(rejects([&] { return g.RemovePose("b", n); }));
    EXPECT_TRUE(rejects([&] { return g.RemoveTwist(n, "A"); }));
    EXPECT_TRUE(rejects([&] { return g.RemoveTwist("b", n); }));
  }
  // A missing coordinate frame is an empty name even beside the empty (optional) body: both
  // default views are the same null view, which once made the frame borrow the body's unset
  // name and pass as twist_not_convertible.
  TwistSpec no_frame;
  no_frame.point = "z";
  no_frame.ref_body = "A";
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kInvalidName, {"name is empty"}, [&] {
    return g.AddTwist(no_frame, LinearNumber(1), AngularNumber(1));
  }));
}

TYPED_TEST(SceneGraphConstraints, InvalidNameAcceptsLongestAndNonAsciiPrintableNames) {
  auto& g = this->graph_;
  const std::string longest(255, 'y');
  EXPECT_TRUE(Accepts(g, g.AddBody(longest)));
  EXPECT_TRUE(Accepts(g, g.AddFrame("Greifer-\xc3\xbc", longest)));                  // "Greifer-ü"
  EXPECT_TRUE(Accepts(g, AddEdge(g, "\xe6\x89\x8b", "H", "Greifer-\xc3\xbc", "")));  // "手"
  EXPECT_TRUE(g.GetPose(PoseSpec::Of("\xe6\x89\x8b").RelativeTo("Greifer-\xc3\xbc")));
}

TYPED_TEST(SceneGraphConstraints, InvalidNameIsReturnedByQueriesWithMissingOrInvalidNames) {
  auto& g = this->graph_;
  BuildTwoTrees(g);
  for (const BadName& bad : BadNames()) {
    SCOPED_TRACE("name \"" + bad.name + "\"");
    const std::string_view n = bad.name;
    for (int field = 0; field < 5; ++field) {
      PoseSpec s = PoseSpec::Of("c").RelativeTo("a");
      std::string_view* slots[] = {&s.point, &s.orientation, &s.ref_point, &s.ref_orientation,
                                   &s.coordinate_frame};
      *slots[field] = n;
      EXPECT_TRUE(
          QueryFails(g, g.GetPose(s), s, ErrorCode::kInvalidName, {"name is missing or invalid"}))
          << "pose field " << field;
    }
    for (int field = 0; field < 3; ++field) {
      PoseSpec s = PoseSpec::Of("c").RelativeTo("a");
      std::string_view* slots[] = {&s.point, &s.ref_point, &s.coordinate_frame};
      *slots[field] = n;
      EXPECT_TRUE(QueryFails(g, g.GetPosition(s), s, ErrorCode::kInvalidName))
          << "position field " << field;
      PoseSpec o = PoseSpec::Of("c").RelativeTo("a");
      std::string_view* o_slots[] = {&o.orientation, &o.ref_orientation, &o.coordinate_frame};
      *o_slots[field] = n;
      EXPECT_TRUE(QueryFails(g, g.GetOrientation(o), o, ErrorCode::kInvalidName))
          << "orientation field " << field;
    }
    for (int field = 0; field < 3; ++field) {
      TwistSpec s = TwistSpec::Of("c").RelativeTo("A").ExpressedIn("a");
      std::string_view* slots[] = {&s.point, &s.ref_body, &s.coordinate_frame};
      *slots[field] = n;
      EXPECT_TRUE(QueryFails(g, g.GetTwist(s), s, ErrorCode::kInvalidName))
          << "twist field " << field;
      EXPECT_TRUE(QueryFails(g, g.GetLinearVelocity(s), s, ErrorCode::kInvalidName))
          << "twist field " << field;
    }
    TwistSpec w;
    w.body = "C";
    w.ref_body = "A";
    w.coordinate_frame = n;
    EXPECT_TRUE(QueryFails(g, g.GetAngularVelocity(w), w, ErrorCode::kInvalidName,
                           {"the coordinate frame name"}));
    if (!n.empty()) {  // an empty body is "take it from the frame"
      PoseSpec s = PoseSpec::Of("c", n).RelativeTo("a");
      EXPECT_TRUE(QueryFails(g, g.GetPose(s), s, ErrorCode::kInvalidName));
      EXPECT_TRUE(QueryFails(g, g.GetPosition(s), s, ErrorCode::kInvalidName));
      EXPECT_TRUE(QueryFails(g, g.GetOrientation(s), s, ErrorCode::kInvalidName));
      const TwistSpec t = TwistSpec::Of("c", n).RelativeTo("A").ExpressedIn("a");
      EXPECT_TRUE(QueryFails(g, g.GetTwist(t), t, ErrorCode::kInvalidName));
    }
  }
}

// ---------------------------------------------------------------------- invalid_number

TYPED_TEST(SceneGraphConstraints, InvalidNumberRejectsNanAndInfInPositionQuaternionMatrixAndTwist) {
  auto& g = this->graph_;
  BuildTwoTrees(g);
  const PoseSpec spec = PoseSpec::Of("z", "Z").RelativeTo("c", "C");
  for (double bad : {kNaN, kInf, -kInf}) {
    for (int i = 0; i < 3; ++i) {
      Eigen::Vector3d p = PositionNumber(1);
      p[i] = bad;
      EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kInvalidNumber,
                                  {"pose of {z}|Z wrt {c}|C", "must be finite"},
                                  [&] { return g.AddPose(spec, RotationNumber(1), p); }));
      Eigen::Vector3d v = LinearNumber(1), w = AngularNumber(1);
      v[i] = bad;
      EXPECT_TRUE(RejectsAndKeeps(
          g, ErrorCode::kInvalidNumber, {"twist of z|Z wrt A", "must be finite"}, [&] {
            return g.AddTwist(TwistSpec::Of("z", "Z").RelativeTo("A").ExpressedIn("z"), v,
                              AngularNumber(1));
          }));
      w[i] = bad;
      EXPECT_TRUE(RejectsAndKeeps(
          g, ErrorCode::kInvalidNumber, {"twist of z|Z wrt A", "must be finite"}, [&] {
            return g.AddTwist(TwistSpec::Of("z", "Z").RelativeTo("A").ExpressedIn("z"),
                              LinearNumber(1), w);
          }));
    }
    for (int i = 0; i < 4; ++i) {
      Eigen::Quaterniond q = RotationNumber(1);
      q.coeffs()[i] = bad;
      EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kInvalidNumber,
                                  {"pose of {z}|Z wrt {c}|C", "quaternion", "must be finite"},
                                  [&] { return g.AddPose(spec, q, PositionNumber(1)); }));
    }
    for (int i = 0; i < 9; ++i) {
      Eigen::Matrix3d R = RotationNumber(1).toRotationMatrix();
      R.data()[i] = bad;
      EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kInvalidNumber,
                                  {"pose of {z}|Z wrt {c}|C", "must be finite"},
                                  [&] { return g.AddPose(spec, R, PositionNumber(1)); }));
    }
  }
  // Updates of existing edges are checked the same way.
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kInvalidNumber, {"pose of {b}|B wrt {a}|A"}, [&] {
    return g.AddPose(PoseSpec::Of("b", "B").RelativeTo("a", "A"), RotationNumber(2),
                     Eigen::Vector3d(0, kNaN, 0));
  }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kInvalidNumber, {"twist of b|B wrt A"}, [&] {
    return g.AddTwist(TwistSpec::Of("b", "B").RelativeTo("A").ExpressedIn("b"), LinearNumber(2),
                      Eigen::Vector3d(kInf, 0, 0));
  }));
}

// ---------------------------------------------------------------------- invalid_rotation

TYPED_TEST(SceneGraphConstraints,
           InvalidRotationRejectsOffUnitQuaternionsNonOrthonormalMatricesAndReflections) {
  auto& g = this->graph_;
  BuildTwoTrees(g);
  const PoseSpec spec = PoseSpec::Of("z", "Z").RelativeTo("c", "C");
  Eigen::Quaterniond q = RotationNumber(1);
  q.coeffs() *= 1.0 + 2e-6;
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kInvalidRotation,
                              {"pose of {z}|Z wrt {c}|C", "quaternion norm differs from 1"},
                              [&] { return g.AddPose(spec, q, PositionNumber(1)); }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kInvalidRotation, {"quaternion norm"}, [&] {
    return g.AddPose(spec, Eigen::Quaterniond(0, 0, 0, 0), PositionNumber(1));
  }));
  Eigen::Matrix3d sheared = RotationNumber(1).toRotationMatrix();
  sheared(0, 1) += 1e-3;
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kInvalidRotation, {"not orthonormal"},
                              [&] { return g.AddPose(spec, sheared, PositionNumber(1)); }));
  const Eigen::Matrix3d scaled = 1.01 * RotationNumber(1).toRotationMatrix();
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kInvalidRotation, {"not orthonormal"},
                              [&] { return g.AddPose(spec, scaled, PositionNumber(1)); }));
  const Eigen::Matrix3d reflection =
      Eigen::Vector3d(1, 1, -1).asDiagonal() * RotationNumber(1).toRotationMatrix();
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kInvalidRotation, {"reflection"},
                              [&] { return g.AddPose(spec, reflection, PositionNumber(1)); }));
}

TYPED_TEST(SceneGraphConstraints, RotationsWithinToleranceAreNormalizedAndMinusQIsTheSameRotation) {
  auto& g = this->graph_;
  BuildTwoTrees(g);
  Eigen::Quaterniond q = RotationNumber(2);
  q.coeffs() *= -(1.0 + 5e-7);  // -q, off unit norm within 1e-6
  ASSERT_TRUE(
      Accepts(g, g.AddPose(PoseSpec::Of("z", "Z").RelativeTo("c", "C"), q, PositionNumber(2))));
  Eigen::Matrix3d R = RotationNumber(3).toRotationMatrix();
  R(0, 1) += 2e-7;  // max |R^T R - I| about 2e-7
  ASSERT_TRUE(
      Accepts(g, g.AddPose(PoseSpec::Of("q2", "Q").RelativeTo("q", "Q"), R, PositionNumber(3))));
  auto X_CZ = g.GetOrientation(PoseSpec::Of("z").RelativeTo("c"));
  ASSERT_TRUE(X_CZ);
  const Eigen::Matrix3d R_CZ = TypeParam::ToMatrix(X_CZ->value);
  EXPECT_TRUE(Near(R_CZ, RotationNumber(2).toRotationMatrix(), 1e-12));
  EXPECT_TRUE(Near(R_CZ.transpose() * R_CZ, Eigen::Matrix3d::Identity(), 1e-12));  // normalized
  auto X_QQ2 = g.GetOrientation(PoseSpec::Of("q2").RelativeTo("q"));
  ASSERT_TRUE(X_QQ2);
  const Eigen::Matrix3d R_QQ2 = TypeParam::ToMatrix(X_QQ2->value);
  EXPECT_TRUE(Near(R_QQ2.transpose() * R_QQ2, Eigen::Matrix3d::Identity(), 1e-12));  // polar factor
  EXPECT_TRUE(Near(R_QQ2, RotationNumber(3).toRotationMatrix(), 1e-6));
}

// ---------------------------------------------------------------------- nodes

TYPED_TEST(SceneGraphConstraints, DuplicateBodyRejectsABodyAlsoWhenAnEdgeCreatedIt) {
  auto& g = this->graph_;
  BuildTwoTrees(g);  // B was created by the pose edge a -> b, P by p -> q
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kDuplicateBody, {"body B already exists"},
                              [&] { return g.AddBody("B"); }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kDuplicateBody, {"body P already exists"},
                              [&] { return g.AddBody("P"); }));
}

TYPED_TEST(SceneGraphConstraints, DuplicateFrameRejectsAFrameAlsoWhenAnEdgeCreatedIt) {
  auto& g = this->graph_;
  BuildTwoTrees(g);
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kDuplicateFrame, {"frame {q}|Q already exists"},
                              [&] { return g.AddFrame("q", "Q"); }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kDuplicateFrame, {"frame {c}|C already exists"},
                              [&] { return g.AddFrame("c", "Z"); }));
}

TYPED_TEST(SceneGraphConstraints, UnknownBodyRejectsFramesOnMissingBodiesTwistRemovalsAndQueries) {
  auto& g = this->graph_;
  BuildTwoTrees(g);
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kUnknownBody,
                              {"frame {n}|Nowhere", "body Nowhere does not exist"},
                              [&] { return g.AddFrame("n", "Nowhere"); }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kUnknownBody, {"body Nowhere does not exist"},
                              [&] { return g.RemoveTwist("b", "Nowhere"); }));
  const PoseSpec pose = PoseSpec::Of("c", "Nowhere").RelativeTo("a");
  EXPECT_TRUE(QueryFails(g, g.GetPose(pose), pose, ErrorCode::kUnknownBody,
                         {"body Nowhere, which does not exist"}));
  EXPECT_TRUE(QueryFails(g, g.GetPosition(pose), pose, ErrorCode::kUnknownBody));
  EXPECT_TRUE(QueryFails(g, g.GetOrientation(pose), pose, ErrorCode::kUnknownBody));
  const PoseSpec ref = PoseSpec::Of("c").RelativeTo("a", "Nowhere");
  EXPECT_TRUE(QueryFails(g, g.GetPose(ref), ref, ErrorCode::kUnknownBody, {"reference body"}));
  const TwistSpec twist = TwistSpec::Of("c").RelativeTo("Nowhere").ExpressedIn("a");
  EXPECT_TRUE(QueryFails(g, g.GetTwist(twist), twist, ErrorCode::kUnknownBody, {"Nowhere"}));
  const TwistSpec moving = TwistSpec::Of("c", "Nowhere").RelativeTo("A").ExpressedIn("a");
  EXPECT_TRUE(
      QueryFails(g, g.GetLinearVelocity(moving), moving, ErrorCode::kUnknownBody, {"Nowhere"}));
}

TYPED_TEST(SceneGraphConstraints, UnknownFrameRejectsRemovalsAndQueriesNamingMissingFrames) {
  auto& g = this->graph_;
  BuildTwoTrees(g);
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kUnknownFrame, {"frame {ghost} does not exist"},
                              [&] { return g.RemovePose("ghost", "a"); }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kUnknownFrame, {"frame {ghost} does not exist"},
                              [&] { return g.RemovePose("b", "ghost"); }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kUnknownFrame, {"frame {ghost} does not exist"},
                              [&] { return g.RemoveTwist("ghost", "A"); }));
  // A body name is not a frame name.
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kUnknownFrame, {"frame {A} does not exist"},
                              [&] { return g.RemoveTwist("A", "A"); }));
  for (int field = 0; field < 5; ++field) {
    PoseSpec s = PoseSpec::Of("c").RelativeTo("a");
    std::string_view* slots[] = {&s.point, &s.orientation, &s.ref_point, &s.ref_orientation,
                                 &s.coordinate_frame};
    *slots[field] = "ghost";
    EXPECT_TRUE(
        QueryFails(g, g.GetPose(s), s, ErrorCode::kUnknownFrame, {"{ghost}, which does not exist"}))
        << "field " << field;
  }
  const PoseSpec s = PoseSpec::Of("ghost").RelativeTo("a");
  EXPECT_TRUE(
      QueryFails(g, g.GetPosition(s), s, ErrorCode::kUnknownFrame, {"point names frame {ghost}"}));
  EXPECT_TRUE(QueryFails(g, g.GetOrientation(s), s, ErrorCode::kUnknownFrame,
                         {"orientation frame names frame {ghost}"}));
  const TwistSpec t = TwistSpec::Of("c").RelativeTo("A").ExpressedIn("ghost");
  EXPECT_TRUE(QueryFails(g, g.GetTwist(t), t, ErrorCode::kUnknownFrame,
                         {"coordinate frame names frame {ghost}"}));
  // The angular velocity has no point argument: the unknown frame is its coordinate frame.
  TwistSpec w;
  w.body = "C";
  w.ref_body = "A";
  w.coordinate_frame = "ghost";
  EXPECT_TRUE(QueryFails(g, g.GetAngularVelocity(w), w, ErrorCode::kUnknownFrame,
                         {"the coordinate frame names frame {ghost}"}));
}

TYPED_TEST(SceneGraphConstraints, FrameWithoutBodyRejectsNewFramesThatNameNoBody) {
  auto& g = this->graph_;
  BuildTwoTrees(g);
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kFrameWithoutBody,
                              {"frame {new}", "must name the body"},
                              [&] { return g.AddFrame("new", ""); }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kFrameWithoutBody,
                              {"frame {new} does not exist and no body is given"},
                              [&] { return AddEdge(g, "new", "", "c", "C"); }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kFrameWithoutBody,
                              {"frame {new} does not exist and no body is given"},
                              [&] { return AddEdge(g, "z", "Z", "new", ""); }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kFrameWithoutBody,
                              {"frame {new} does not exist and no body is given"},
                              [&] { return AddScrewTwist(g, "new", "", "A"); }));
  // Named with a body, the same adds create the frame (and the body).
  EXPECT_TRUE(Accepts(g, AddEdge(g, "new", "N", "c", "C")));
  EXPECT_EQ(g.body_name(g.body_of(g.FindFrame("new"))), "N");
}

TYPED_TEST(SceneGraphConstraints, FrameBodyMismatchRejectsFramesNamedWithTheWrongBody) {
  auto& g = this->graph_;
  BuildTwoTrees(g);
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kFrameBodyMismatch,
                              {"frame {z} is attached to body Z, not C"},
                              [&] { return AddEdge(g, "z", "C", "c", "C"); }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kFrameBodyMismatch,
                              {"frame {c} is attached to body C, not Z"},
                              [&] { return AddEdge(g, "z", "Z", "c", "Z"); }));
  // A point or reference point that is the origin of a frame of another body.
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kFrameBodyMismatch,
                              {"point q is the origin of {q}|Q, not of a frame of body Z"}, [&] {
                                return g.AddPose(
                                    PoseSpec::Of("z", "Z").RelativeTo("c", "C").AtPoint("q"),
                                    RotationNumber(1), PositionNumber(1));
                              }));
  EXPECT_TRUE(RejectsAndKeeps(
      g, ErrorCode::kFrameBodyMismatch,
      {"reference point b is the origin of {b}|B, not of a frame of body C"}, [&] {
        return g.AddPose(PoseSpec::Of("z", "Z").RelativeTo("c", "C").RelativeToPoint("b"),
                         RotationNumber(1), PositionNumber(1));
      }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kFrameBodyMismatch, {"{b}|B is not on body C"},
                              [&] { return AddScrewTwist(g, "b", "C", "Z"); }));
  const PoseSpec pose = PoseSpec::Of("c", "B").RelativeTo("a");
  EXPECT_TRUE(QueryFails(g, g.GetPose(pose), pose, ErrorCode::kFrameBodyMismatch,
                         {"{c} is attached to body C"}));
  EXPECT_TRUE(QueryFails(g, g.GetPosition(pose), pose, ErrorCode::kFrameBodyMismatch));
  EXPECT_TRUE(QueryFails(g, g.GetOrientation(pose), pose, ErrorCode::kFrameBodyMismatch));
  PoseSpec point = PoseSpec::Of("c").RelativeTo("a").AtPoint("b");  // point b|B with [c]|C
  EXPECT_TRUE(QueryFails(g, g.GetPose(point), point, ErrorCode::kFrameBodyMismatch,
                         {"point {b} is attached to body B"}));
}

// ---------------------------------------------------------------------- edges: shape

TYPED_TEST(SceneGraphConstraints, SelfEdgeRejectsAPoseOfAFrameWrtItself) {
  auto& g = this->graph_;
  BuildTwoTrees(g);
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kSelfEdge,
                              {"pose of {c}|C wrt {c}|C", "from {c} to itself"},
                              [&] { return AddEdge(g, "c", "C", "c", "C"); }));
  // Also for a frame that does not exist yet (nothing may be created).
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kSelfEdge, {"from {new} to itself"},
                              [&] { return AddEdge(g, "new", "N", "new", "N"); }));
}

TYPED_TEST(SceneGraphConstraints, TwistSameBodyRejectsATwistOfABodyWrtItself) {
  auto& g = this->graph_;
  BuildTwoTrees(g);
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kTwistSameBody,
                              {"twist of c|C wrt C", "body C relative to itself"},
                              [&] { return AddScrewTwist(g, "c", "C", "C"); }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kTwistSameBody, {"body N relative to itself"},
                              [&] { return AddScrewTwist(g, "new", "N", "N"); }));
}

TYPED_TEST(SceneGraphConstraints, TwistNotConvertibleRejectsACoordinateFrameOutsideThePointsTree) {
  auto& g = this->graph_;
  BuildTwoTrees(g);
  const auto twist_in = [&](std::string_view point, std::string_view body, std::string_view r) {
    return g.AddTwist(TwistSpec::Of(point, body).RelativeTo("Z").ExpressedIn(r), LinearNumber(1),
                      AngularNumber(1));
  };
  EXPECT_TRUE(
      RejectsAndKeeps(g, ErrorCode::kTwistNotConvertible,
                      {"twist of c|C wrt Z in [p]", "[p] must be a frame in the pose tree of {c}"},
                      [&] { return twist_in("c", "C", "p"); }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kTwistNotConvertible,
                              {"[ghost] must be a frame in the pose tree of {c}"},
                              [&] { return twist_in("c", "C", "ghost"); }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kTwistNotConvertible,
                              {"[a] must be a frame in the pose tree of {new}"},
                              [&] { return twist_in("new", "N", "a"); }));
  // Inside the tree it is converted: [a] -> [c] with the orientation of [a] wrt [c].
  ASSERT_TRUE(Accepts(g, twist_in("c", "C", "a")));
  auto V = g.GetTwist(TwistSpec::Of("c").RelativeTo("Z").ExpressedIn("a"));
  ASSERT_TRUE(V);
  EXPECT_TRUE(Near(V->linear, LinearNumber(1)));
  EXPECT_TRUE(Near(V->angular, AngularNumber(1)));
}

TYPED_TEST(SceneGraphConstraints,
           ConstantPoseChangeRejectsANewValueAndKeepsTheStoredOneForTheSameValue) {
  auto& g = this->graph_;
  BuildTwoTrees(g);  // a -> a2 is constant (both on A), value Pose(3)
  EXPECT_TRUE(
      RejectsAndKeeps(g, ErrorCode::kConstantPoseChange,
                      {"pose of {a2}|A wrt {a}|A", "{a2}|A and {a}|A are both fixed to body A",
                       "already set (position [1.5, -0.75, 1.375])"},
                      [&] { return AddEdge(g, "a2", "A", "a", "A", 4); }));
  // Just outside the tolerances: one rotation entry 1e-5 off (re-normalized), position off
  // by 2e-6 * |p| along p.
  Eigen::Quaterniond q_off =
      RotationNumber(3) * Eigen::Quaterniond(Eigen::AngleAxisd(2e-5, Eigen::Vector3d::UnitZ()));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kConstantPoseChange, {"{a2}|A and {a}|A"}, [&] {
    return g.AddPose(PoseSpec::Of("a2").RelativeTo("a"), q_off, PositionNumber(3));
  }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kConstantPoseChange, {"{a2}|A and {a}|A"}, [&] {
    return g.AddPose(PoseSpec::Of("a2").RelativeTo("a"), RotationNumber(3),
                     PositionNumber(3) * (1.0 + 2e-6));
  }));
  // Within the tolerances (rotation entries within 1e-6, position within 1e-6 |p|): accepted
  // as a no-op that keeps the stored value, to the last bit.
  const std::string before = Dump(g);
  Eigen::Quaterniond q_near =
      RotationNumber(3) * Eigen::Quaterniond(Eigen::AngleAxisd(2e-7, Eigen::Vector3d::UnitZ()));
  q_near.coeffs() = -q_near.coeffs();
  EXPECT_TRUE(Accepts(
      g, g.AddPose(PoseSpec::Of("a2").RelativeTo("a"), q_near, PositionNumber(3) * (1.0 + 5e-7))));
  EXPECT_TRUE(Accepts(
      g, g.AddPose(PoseSpec::Of("a2", "A").RelativeTo("a", "A"),
                   Eigen::Matrix3d(RotationNumber(3).toRotationMatrix()), PositionNumber(3))));
  EXPECT_EQ(Dump(g), before);
  // Removing the edge and adding it again is the way to recalibrate.
  ASSERT_TRUE(Accepts(g, g.RemovePose("a2", "a")));
  ASSERT_TRUE(Accepts(g, AddEdge(g, "a2", "A", "a", "A", 4)));
  auto X_AA2 = g.GetPosition(PoseSpec::Of("a2").RelativeTo("a"));
  ASSERT_TRUE(X_AA2);
  EXPECT_TRUE(Near(X_AA2->value, PositionNumber(4)));
}

// ---------------------------------------------------------------------- edges: pose topology

TYPED_TEST(SceneGraphConstraints, MultiplePoseParentsRejectsASecondParentAndCreatesNothing) {
  auto& g = this->graph_;
  BuildTwoTrees(g);
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kMultiplePoseParents,
                              {"pose of {c}|C wrt {z}|Z", "{c}|C already has a pose parent {b}|B"},
                              [&] { return AddEdge(g, "c", "C", "z", "Z"); }));
  // A parent that does not exist yet is not created (Dump compares the name table too).
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kMultiplePoseParents,
                              {"{q}|Q already has a pose parent {p}|P"},
                              [&] { return AddEdge(g, "q", "Q", "new", "NewBody"); }));
  EXPECT_FALSE(g.FindBody("NewBody").is_valid());
  EXPECT_FALSE(g.names().Find("new").is_valid());
}

TYPED_TEST(SceneGraphConstraints, PoseCycleRejectsAnEdgeThatClosesAShortOrLongCycle) {
  auto& g = this->graph_;
  BuildTwoTrees(g);  // a -> b -> c: a is the root
  EXPECT_TRUE(RejectsAndKeeps(
      g, ErrorCode::kPoseCycle,
      {"pose of {a}|A wrt {c}|C", "{c}|C is already connected below {a}|A", "would close a cycle"},
      [&] { return AddEdge(g, "a", "A", "c", "C"); }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kPoseCycle, {"{b}|B is already connected below {a}|A"},
                              [&] { return AddEdge(g, "a", "A", "b", "B"); }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kPoseCycle, {"{a2}|A is already connected below {a}|A"},
                              [&] { return AddEdge(g, "a", "A", "a2", "A"); }));  // same body
}

TYPED_TEST(SceneGraphConstraints, DuplicatePosePathRejectsASecondChainBetweenTwoBodies) {
  auto& g = this->graph_;
  BuildTwoTrees(g);
  // A second tree that also holds C, {c2}|C -> {x}|X; linking it to the tree of {a} (which
  // holds {c}|C) would reach C twice.
  ASSERT_TRUE(Accepts(g, AddEdge(g, "x", "X", "c2", "C")));
  EXPECT_TRUE(RejectsAndKeeps(
      g, ErrorCode::kDuplicatePosePath,
      {"pose of {c2}|C wrt {b}|B", "body C would be reachable twice",
       "from {b}|B: through {b}|B -> {c}|C", "through the new edge, {b}|B -> {c2}|C",
       "Give {c2} its pose relative to a frame of C (such as {c}|C)"},
      [&] { return AddEdge(g, "c2", "C", "b", "B"); }));
  // Linking the other way round is the same second chain.
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kDuplicatePosePath, {"body C would be reachable twice"},
                              [&] { return AddEdge(g, "a", "A", "x", "X"); }));
}

TYPED_TEST(SceneGraphConstraints, DuplicatePosePathRejectsANewTailFrameOnABodyOfTheHeadsTree) {
  auto& g = this->graph_;
  BuildTwoTrees(g);
  // {a} is a root whose tree holds C; a new frame {c9}|C as its parent would reach C twice.
  EXPECT_TRUE(RejectsAndKeeps(
      g, ErrorCode::kDuplicatePosePath,
      {"pose of {a}|A wrt {c9}|C", "body C would be reachable twice from {c9}|C: at {c9}|C itself",
       "through the new edge, {c9}|C -> {a}|A -> {b}|B -> {c}|C",
       "Give {c9} its pose relative to a frame of C (such as {c}|C)"},
      [&] { return AddEdge(g, "a", "A", "c9", "C"); }));
  // And a new head frame {b9}|B under {c}, whose tree already holds B.
  EXPECT_TRUE(RejectsAndKeeps(
      g, ErrorCode::kDuplicatePosePath,
      {"pose of {b9}|B wrt {c}|C", "body B would be reachable twice from {b}|B: at {b}|B itself",
       "through the new edge, {b}|B -> {c}|C -> {b9}|B",
       "Give {b9} its pose relative to a frame of B (such as {b}|B)"},
      [&] { return AddEdge(g, "b9", "B", "c", "C"); }));
}

TYPED_TEST(SceneGraphConstraints, DuplicatePosePathAcceptsListing1ConstantPoseOfF1WrtO1) {
  auto& g = this->graph_;
  BuildSprayPaintingPoses(g);
  // o1 already hangs under c under b; f1 wrt o1 on O1 adds no second path between bodies. The
  // paper's literal rule ("no descendant of the head may have the body of a descendant of the
  // source's root") would refuse it; spec P3 accepts it, as the paper's own Listing 1 needs.
  ASSERT_TRUE(Accepts(g, g.AddPose(PoseSpec::Of("f1", "O1").RelativeTo("o1", "O1"),
                                   Eigen::Quaterniond(Eigen::AngleAxisd(std::numbers::pi / 4,
                                                                        Eigen::Vector3d::UnitZ())),
                                   Eigen::Vector3d(0.02, 0, 0.2))));
  // Also between a lone frame {f2} of O1 that exists already and {f1}.
  ASSERT_TRUE(Accepts(g, g.AddFrame("f2", "O1")));
  ASSERT_TRUE(Accepts(g, AddEdge(g, "f2", "", "f1", "")));
  // Listing 2: the pose of f1 wrt o2 is now defined.
  auto X_O2F1 = g.GetPose(PoseSpec::Of("f1", "O1").RelativeTo("o2", "O2"));
  ASSERT_TRUE(X_O2F1);
  const Eigen::Isometry3d X_BO1 = IsometryNumber(1) * IsometryNumber(2);
  const Eigen::Isometry3d X_BO2 = IsometryNumber(4) * IsometryNumber(3);
  Eigen::Isometry3d X_O1F1 = Eigen::Isometry3d::Identity();
  X_O1F1.linear() =
      Eigen::AngleAxisd(std::numbers::pi / 4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  X_O1F1.translation() = Eigen::Vector3d(0.02, 0, 0.2);
  const Eigen::Isometry3d X_O2F1_expected = X_BO2.inverse() * X_BO1 * X_O1F1;
  EXPECT_TRUE(
      Near(TypeParam::ToMatrix(TypeParam::RotationOf(X_O2F1->value)), X_O2F1_expected.linear()));
  EXPECT_TRUE(Near(TypeParam::TranslationOf(X_O2F1->value), X_O2F1_expected.translation()));
}

TYPED_TEST(SceneGraphConstraints,
           DuplicatePosePathRejectsASameBodyEdgeBetweenTreesSharingAThirdBody) {
  auto& g = this->graph_;
  // Two trees, each holding a frame of A and a frame of C:
  //
  //   {a1}|A        {a2}|A
  //     |             |
  //   {c1}|C        {c2}|C
  //
  // The same-body edge a1 -> a2 is allowed to share A, but C would be reached twice.
  ASSERT_TRUE(Accepts(g, AddEdge(g, "c1", "C", "a1", "A", 1)));
  ASSERT_TRUE(Accepts(g, AddEdge(g, "c2", "C", "a2", "A", 2)));
  EXPECT_TRUE(RejectsAndKeeps(
      g, ErrorCode::kDuplicatePosePath,
      {"pose of {a2}|A wrt {a1}|A", "body C would be reachable twice",
       "from {a1}|A: through {a1}|A -> {c1}|C", "through the new edge, {a1}|A -> {a2}|A -> {c2}|C",
       "(such as {c1}|C and {c2}|C)"},
      [&] { return AddEdge(g, "a2", "A", "a1", "A", 3); }));
  // Without the third body it is fine.
  ASSERT_TRUE(Accepts(g, g.RemovePose("c2", "a2")));
  EXPECT_TRUE(Accepts(g, AddEdge(g, "a2", "A", "a1", "A", 3)));
}

// ---------------------------------------------------------------------- edges: twist topology

TYPED_TEST(SceneGraphConstraints, TwistMergeConflictRejectsJoiningTreesWhoseTwistsWouldFormACycle) {
  auto& g = this->graph_;
  // W4: while c1 and c3 are in different pose trees, A ~> {c1}|C and A ~> {c3}|C are both
  // legal (each tree's TG is the single edge A-C). Joining the trees would make two twist
  // paths between A and C.
  //
  //   A ~> {c1}|C      A ~> {c3}|C        then c1 -> c3 ?
  ASSERT_TRUE(Accepts(g, AddScrewTwist(g, "c1", "C", "A", 1)));
  ASSERT_TRUE(Accepts(g, AddScrewTwist(g, "c3", "C", "A", 2)));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kTwistMergeConflict,
                              {"pose of {c3}|C wrt {c1}|C",
                               "joining the pose trees of {c1}|C and {c3}|C", "two twist paths"},
                              [&] { return AddEdge(g, "c3", "C", "c1", "C"); }));
  // Through a third body too: A ~> {b}|B and B ~> {c4}|C in one tree, A ~> {c5}|C in another.
  ASSERT_TRUE(Accepts(g, AddEdge(g, "c4", "C", "b", "B")));
  ASSERT_TRUE(Accepts(g, AddScrewTwist(g, "b", "B", "A", 3)));
  ASSERT_TRUE(Accepts(g, AddScrewTwist(g, "c4", "C", "B", 4)));
  ASSERT_TRUE(Accepts(g, AddScrewTwist(g, "c5", "C", "A", 5)));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kTwistMergeConflict, {"{c5}|C"},
                              [&] { return AddEdge(g, "c5", "C", "c4", "C"); }));
  // Removing one twist makes the join legal.
  ASSERT_TRUE(Accepts(g, g.RemoveTwist("c3", "A")));
  EXPECT_TRUE(Accepts(g, AddEdge(g, "c3", "C", "c1", "C")));
}

TYPED_TEST(SceneGraphConstraints,
           MultipleTwistParentsRejectsASecondReferenceBodyAndCreatesNothing) {
  auto& g = this->graph_;
  BuildTwoTrees(g);  // A ~> {b}
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kMultipleTwistParents,
                              {"twist of b wrt Z", "{b}|B already has a twist parent: body A"},
                              [&] { return AddScrewTwist(g, "b", "", "Z"); }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kMultipleTwistParents,
                              {"{b}|B already has a twist parent: body A"},
                              [&] { return AddScrewTwist(g, "b", "B", "NewBody"); }));
  EXPECT_FALSE(g.FindBody("NewBody").is_valid());
}

TYPED_TEST(SceneGraphConstraints, DuplicateTwistPathRejectsAParallelEdgeOrACycleInOnePoseTree) {
  auto& g = this->graph_;
  BuildTwoTrees(g);  // tree of a: bodies A, B, C; A ~> {b}
  // Parallel: another frame of B in the same tree.
  ASSERT_TRUE(Accepts(g, AddEdge(g, "b2", "B", "b", "B")));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kDuplicateTwistPath,
                              {"the twist of B relative to A already follows", "{b2}|B"},
                              [&] { return AddScrewTwist(g, "b2", "B", "A"); }));
  // Reversed: B ~> {a} is the inverse of what A ~> {b} gives.
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kDuplicateTwistPath, {"the twist of A relative to B"},
                              [&] { return AddScrewTwist(g, "a", "A", "B"); }));
  // A cycle A - B - C - A.
  ASSERT_TRUE(Accepts(g, AddScrewTwist(g, "c", "C", "B")));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kDuplicateTwistPath, {"the twist of A relative to C"},
                              [&] { return AddScrewTwist(g, "a2", "A", "C"); }));
  // In another pose tree the same bodies are independent.
  EXPECT_TRUE(Accepts(g, AddScrewTwist(g, "z", "Z", "A")));
  EXPECT_TRUE(Accepts(g, AddEdge(g, "b3", "B", "p", "P")));
  EXPECT_TRUE(Accepts(g, AddScrewTwist(g, "b3", "B", "A")));
}

// ---------------------------------------------------------------------- removal

TYPED_TEST(SceneGraphConstraints, NoSuchEdgeRejectsRemovingMissingPoseAndTwistEdges) {
  auto& g = this->graph_;
  BuildTwoTrees(g);
  EXPECT_TRUE(
      RejectsAndKeeps(g, ErrorCode::kNoSuchEdge,
                      {"there is no pose edge {b}|B -> {a}|A", "({a}|A has no pose parent)"},
                      [&] { return g.RemovePose("a", "b"); }));  // wrong direction
  EXPECT_TRUE(RejectsAndKeeps(
      g, ErrorCode::kNoSuchEdge,
      {"there is no pose edge {a}|A -> {c}|C", "(the pose parent of {c}|C is {b}|B)"},
      [&] { return g.RemovePose("c", "a"); }));  // grandparent
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kNoSuchEdge,
                              {"there is no twist edge P -> {b}|B", "(its twist parent is A)"},
                              [&] { return g.RemoveTwist("b", "P"); }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kNoSuchEdge,
                              {"there is no twist edge A -> {c}|C", "({c}|C has no twist parent)"},
                              [&] { return g.RemoveTwist("c", "A"); }));
  // After a removal, removing again is no_such_edge.
  ASSERT_TRUE(Accepts(g, g.RemovePose("q", "p")));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kNoSuchEdge, {"({q}|Q has no pose parent)"},
                              [&] { return g.RemovePose("q", "p"); }));
  ASSERT_TRUE(Accepts(g, g.RemoveTwist("q", "P")));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kNoSuchEdge, {"({q}|Q has no twist parent)"},
                              [&] { return g.RemoveTwist("q", "P"); }));
}

// ---------------------------------------------------------------------- query paths

TYPED_TEST(SceneGraphConstraints, NoPosePathIsReturnedForFramesInDifferentPoseTrees) {
  auto& g = this->graph_;
  BuildTwoTrees(g);
  const PoseSpec pose = PoseSpec::Of("q").RelativeTo("c");
  EXPECT_TRUE(QueryFails(g, g.GetPose(pose), pose, ErrorCode::kNoPosePath,
                         {"{q} and {c} are in different pose trees"}));
  EXPECT_TRUE(QueryFails(g, g.GetPosition(pose), pose, ErrorCode::kNoPosePath, {"{q} and {c}"}));
  EXPECT_TRUE(QueryFails(g, g.GetOrientation(pose), pose, ErrorCode::kNoPosePath, {"{q} and {c}"}));
  // Only the coordinate frame elsewhere.
  const PoseSpec in_q = PoseSpec::Of("b").RelativeTo("c").ExpressedIn("q");
  EXPECT_TRUE(QueryFails(g, g.GetPose(in_q), in_q, ErrorCode::kNoPosePath, {"{q} and {c}"}));
  EXPECT_TRUE(QueryFails(g, g.GetPosition(in_q), in_q, ErrorCode::kNoPosePath));
  EXPECT_TRUE(QueryFails(g, g.GetOrientation(in_q), in_q, ErrorCode::kNoPosePath));
  // Only the point, or only the reference point, elsewhere: a frame of the right body in
  // another tree.
  ASSERT_TRUE(Accepts(g, AddEdge(g, "b3", "B", "p", "P")));
  const PoseSpec at_b3 = PoseSpec::Of("b").RelativeTo("c").AtPoint("b3");
  EXPECT_TRUE(QueryFails(g, g.GetPose(at_b3), at_b3, ErrorCode::kNoPosePath, {"{b3} and {b}"}));
  EXPECT_TRUE(QueryFails(g, g.GetPosition(at_b3), at_b3, ErrorCode::kNoPosePath));
  const PoseSpec from_b3 = PoseSpec::Of("c").RelativeTo("b").RelativeToPoint("b3");
  EXPECT_TRUE(QueryFails(g, g.GetPose(from_b3), from_b3, ErrorCode::kNoPosePath, {"{b3} and {b}"}));
  // A twist whose point and coordinate frame are in different trees, even between bodies
  // with a twist path.
  const TwistSpec twist = TwistSpec::Of("b").RelativeTo("A").ExpressedIn("q");
  EXPECT_TRUE(QueryFails(g, g.GetTwist(twist), twist, ErrorCode::kNoPosePath, {"{q} and {b}"}));
  EXPECT_TRUE(QueryFails(g, g.GetLinearVelocity(twist), twist, ErrorCode::kNoPosePath));
}

TYPED_TEST(SceneGraphConstraints, NoTwistPathIsReturnedWhenNoTwistEdgesJoinTheBodies) {
  auto& g = this->graph_;
  BuildTwoTrees(g);  // tree of a: A ~> {b}; tree of p: P ~> {q}
  const TwistSpec c_wrt_a = TwistSpec::Of("c").RelativeTo("A").ExpressedIn("c");
  EXPECT_TRUE(QueryFails(g, g.GetTwist(c_wrt_a), c_wrt_a, ErrorCode::kNoTwistPath,
                         {"no twist path joins body C and body A"}));
  // P ~> {q} lives in the other pose tree: it does not join P and Q in this one.
  const TwistSpec q_here = TwistSpec::Of("b", "Q").RelativeTo("P").ExpressedIn("b");
  EXPECT_TRUE(
      QueryFails(g, g.GetTwist(q_here), q_here, ErrorCode::kNoTwistPath, {"body Q and body P"}));
  TwistSpec w;
  w.body = "C";
  w.ref_body = "A";
  w.coordinate_frame = "a";
  EXPECT_TRUE(QueryFails(g, g.GetAngularVelocity(w), w, ErrorCode::kNoTwistPath));
  // The same body is always joined: zero.
  auto zero = g.GetTwist(TwistSpec::Of("c").RelativeTo("C").ExpressedIn("a"));
  ASSERT_TRUE(zero);
  EXPECT_TRUE(Near(zero->linear, Eigen::Vector3d::Zero()));
  EXPECT_TRUE(Near(zero->angular, Eigen::Vector3d::Zero()));
  // B wrt A works at any point of the tree, e.g. at c: v moves with w x (p_c - p_b).
  auto V = g.GetTwist(TwistSpec::Of("c", "B").RelativeTo("A").ExpressedIn("b"));
  ASSERT_TRUE(V);
  EXPECT_TRUE(Near(V->angular, AngularNumber(1)));
  EXPECT_TRUE(Near(V->linear, LinearNumber(1) + AngularNumber(1).cross(PositionNumber(2))));
}

// ---------------------------------------------------------------------- error order (§4)

TYPED_TEST(SceneGraphConstraints, AddErrorOrderNameThenNumberThenRotationThenNodes) {
  auto& g = this->graph_;
  BuildTwoTrees(g);
  const Eigen::Vector3d p_nan(kNaN, 0, 0);
  const Eigen::Quaterniond q_bad(2, 0, 0, 0);
  // invalid_name before invalid_number.
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kInvalidName, {"coordinate frame: name is empty"}, [&] {
    return g.AddPose(PoseSpec::Of("z", "Z").RelativeTo("c", "C").ExpressedIn(""), q_bad, p_nan);
  }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kInvalidName, {"name is empty"}, [&] {
    return g.AddTwist(TwistSpec::Of("z", "Z").RelativeTo(""), Eigen::Vector3d(kNaN, 0, 0),
                      AngularNumber(1));
  }));
  // invalid_number before invalid_rotation (also NaN inside the quaternion itself).
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kInvalidNumber, {"must be finite"}, [&] {
    return g.AddPose(PoseSpec::Of("z", "Z").RelativeTo("c", "C"), q_bad, p_nan);
  }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kInvalidNumber, {"quaternion component 0"}, [&] {
    return g.AddPose(PoseSpec::Of("z", "Z").RelativeTo("c", "C"), Eigen::Quaterniond(kNaN, 5, 0, 0),
                     PositionNumber(1));
  }));
  // invalid_rotation before node resolution (frame_body_mismatch, frame_without_body).
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kInvalidRotation, {"quaternion norm"}, [&] {
    return g.AddPose(PoseSpec::Of("z", "C").RelativeTo("new", ""), q_bad, PositionNumber(1));
  }));
  // node resolution before self_edge.
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kFrameBodyMismatch,
                              {"frame {c} is attached to body C, not B"},
                              [&] { return AddEdge(g, "c", "B", "c", "B"); }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kFrameWithoutBody, {"frame {new}"},
                              [&] { return AddEdge(g, "new", "", "new", ""); }));
  // self_edge before pose_not_convertible ([r] is in no tree of the pair).
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kSelfEdge, {"to itself"}, [&] {
    return g.AddPose(PoseSpec::Of("c").RelativeTo("c").ExpressedIn("q"), RotationNumber(1),
                     PositionNumber(1));
  }));
}

TYPED_TEST(SceneGraphConstraints,
           AddErrorOrderConversionThenConstantThenParentsThenCycleThenPaths) {
  auto& g = this->graph_;
  BuildTwoTrees(g);
  if constexpr (std::is_same_v<TypeParam, coord::QuaternionBackend>) {
    // pose_not_convertible before constant_pose_change: a -> a2 is constant and [q] is not in
    // the tree of {a} (the value differs too).
    EXPECT_TRUE(RejectsAndKeeps(
        g, ErrorCode::kPoseNotConvertible, {"[q] must be a frame in the pose tree of {a}"}, [&] {
          return g.AddPose(PoseSpec::Of("a2").RelativeTo("a").ExpressedIn("q"), RotationNumber(7),
                           PositionNumber(7));
        }));
  }
  // multiple_pose_parents before pose_cycle: {b} has a parent and {c} is below it.
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kMultiplePoseParents,
                              {"{b}|B already has a pose parent {a}|A"},
                              [&] { return AddEdge(g, "b", "B", "c", "C"); }));
  // pose_cycle before duplicate_pose_path: closing a cycle always shares bodies too.
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kPoseCycle, {"{c}|C is already connected below {a}|A"},
                              [&] { return AddEdge(g, "a", "A", "c", "C"); }));
  // duplicate_pose_path before twist_merge_conflict: tree of {p} gets a frame of C and the
  // twist B ~> {c8}; joining it under {c} would share C and make a twist cycle A-B... B-C.
  ASSERT_TRUE(Accepts(g, AddEdge(g, "c8", "C", "q", "Q")));
  ASSERT_TRUE(Accepts(g, AddScrewTwist(g, "c", "C", "B")));
  ASSERT_TRUE(Accepts(g, AddScrewTwist(g, "c8", "C", "B")));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kDuplicatePosePath, {"body C would be reachable twice"},
                              [&] { return AddEdge(g, "p", "P", "c", "C"); }));
}

TYPED_TEST(SceneGraphConstraints, TwistErrorOrderFollowsTheSpec) {
  auto& g = this->graph_;
  BuildTwoTrees(g);  // A ~> {b}, tree of a holds A, B, C
  const Eigen::Vector3d v_nan(kNaN, 0, 0);
  // frame_body_mismatch before twist_same_body.
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kFrameBodyMismatch, {"{b}|B is not on body A"},
                              [&] { return AddScrewTwist(g, "b", "A", "A"); }));
  // invalid_number before frame_body_mismatch.
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kInvalidNumber, {"must be finite"}, [&] {
    return g.AddTwist(TwistSpec::Of("b", "A").RelativeTo("A").ExpressedIn("b"), v_nan,
                      AngularNumber(1));
  }));
  // twist_same_body before twist_not_convertible.
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kTwistSameBody, {"body B relative to itself"}, [&] {
    return g.AddTwist(TwistSpec::Of("b").RelativeTo("B").ExpressedIn("q"), LinearNumber(1),
                      AngularNumber(1));
  }));
  // twist_not_convertible before multiple_twist_parents.
  EXPECT_TRUE(RejectsAndKeeps(
      g, ErrorCode::kTwistNotConvertible, {"[q] must be a frame in the pose tree of {b}"}, [&] {
        return g.AddTwist(TwistSpec::Of("b").RelativeTo("Z").ExpressedIn("q"), LinearNumber(1),
                          AngularNumber(1));
      }));
  // multiple_twist_parents before duplicate_twist_path: {c} gets B ~> {c}; then A ~> {c} has
  // both a second parent and a second path A-B-C.
  ASSERT_TRUE(Accepts(g, AddScrewTwist(g, "c", "C", "B")));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kMultipleTwistParents,
                              {"{c}|C already has a twist parent: body B"},
                              [&] { return AddScrewTwist(g, "c", "C", "A"); }));
}

TYPED_TEST(SceneGraphConstraints, RemoveAndFrameErrorOrdersFollowTheSpec) {
  auto& g = this->graph_;
  BuildTwoTrees(g);
  // Remove: invalid_name before unknown_frame before no_such_edge.
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kInvalidName, {"name is empty"},
                              [&] { return g.RemovePose("ghost", ""); }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kUnknownFrame, {"{ghost}"},
                              [&] { return g.RemovePose("ghost", "c"); }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kInvalidName, {"name is empty"},
                              [&] { return g.RemoveTwist("ghost", ""); }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kUnknownFrame, {"{ghost}"},
                              [&] { return g.RemoveTwist("ghost", "Nowhere"); }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kUnknownBody, {"Nowhere"},
                              [&] { return g.RemoveTwist("c", "Nowhere"); }));
  // Frame: invalid_name before frame_without_body before duplicate_frame before unknown_body.
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kInvalidName, {"name is empty"},
                              [&] { return g.AddFrame("", ""); }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kFrameWithoutBody, {"{c}"},
                              [&] { return g.AddFrame("c", ""); }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kDuplicateFrame, {"{c}|C already exists"},
                              [&] { return g.AddFrame("c", "Nowhere"); }));
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kUnknownBody, {"Nowhere"},
                              [&] { return g.AddFrame("new", "Nowhere"); }));
}

TYPED_TEST(SceneGraphConstraints, QueryErrorOrderFollowsTheSpec) {
  auto& g = this->graph_;
  BuildTwoTrees(g);
  // invalid_name before unknown_frame.
  PoseSpec s = PoseSpec::Of("ghost").RelativeTo("c");
  s.coordinate_frame = "";
  EXPECT_TRUE(QueryFails(g, g.GetPose(s), s, ErrorCode::kInvalidName));
  // unknown_frame before unknown_body.
  s = PoseSpec::Of("ghost", "Nowhere").RelativeTo("c");
  EXPECT_TRUE(QueryFails(g, g.GetPose(s), s, ErrorCode::kUnknownFrame));
  // unknown_body before frame_body_mismatch.
  s = PoseSpec::Of("c", "Nowhere").RelativeTo("a", "B");
  EXPECT_TRUE(QueryFails(g, g.GetPose(s), s, ErrorCode::kUnknownBody));
  // frame_body_mismatch before no_pose_path.
  s = PoseSpec::Of("q", "C").RelativeTo("a");
  EXPECT_TRUE(QueryFails(g, g.GetPose(s), s, ErrorCode::kFrameBodyMismatch));
  EXPECT_TRUE(QueryFails(g, g.GetPosition(s), s, ErrorCode::kFrameBodyMismatch));
  EXPECT_TRUE(QueryFails(g, g.GetOrientation(s), s, ErrorCode::kFrameBodyMismatch));
  // no_pose_path before no_twist_path (C and P are not twist-joined either).
  const TwistSpec t = TwistSpec::Of("c").RelativeTo("P").ExpressedIn("q");
  EXPECT_TRUE(QueryFails(g, g.GetTwist(t), t, ErrorCode::kNoPosePath));
  // unknown_frame before unknown_body for twists.
  const TwistSpec u = TwistSpec::Of("ghost").RelativeTo("Nowhere").ExpressedIn("c");
  EXPECT_TRUE(QueryFails(g, g.GetTwist(u), u, ErrorCode::kUnknownFrame));
}

// ---------------------------------------------------------------------- accepted operations

TYPED_TEST(SceneGraphConstraints, AddsCreateMissingFramesAndBodiesFromTheSemantics) {
  auto& g = this->graph_;
  ASSERT_TRUE(Accepts(g, AddEdge(g, "c", "C", "b", "B")));
  ASSERT_TRUE(Accepts(g, AddScrewTwist(g, "o1", "O1", "C")));
  EXPECT_EQ(g.num_bodies(), 3u);
  EXPECT_EQ(g.num_frames(), 3u);
  EXPECT_EQ(g.body_name(g.body_of(g.FindFrame("o1"))), "O1");
  EXPECT_TRUE(g.FindBody("B").is_valid());
  EXPECT_EQ(g.twist_parent(g.FindFrame("o1")), g.FindBody("C"));
}

TYPED_TEST(SceneGraphConstraints, UpdatingACrossBodyEdgeChangesQueriesButNotTheTopology) {
  auto& g = this->graph_;
  BuildTwoTrees(g);
  auto topology = [&] {
    std::string out;
    for (std::string_view f : {"a", "b", "c", "a2", "p", "q", "z"}) {
      const FrameIndex i = g.FindFrame(f);
      out += std::string(f) + "<-" +
             (g.pose_parent(i).is_valid() ? std::string(g.frame_name(g.pose_parent(i))) : "-") +
             " root " + std::string(g.frame_name(g.tree_root(i))) + "; ";
    }
    return out;
  };
  const std::string before = topology();
  const std::size_t edges = g.num_pose_edges();
  // a -> b -> c: X_AC = X_AB X_BC; change X_BC (a joint moves) and X_AB.
  ASSERT_TRUE(Accepts(g, AddEdge(g, "c", "C", "b", "B", 5)));
  ASSERT_TRUE(Accepts(
      g, g.AddPose(PoseSpec::Of("b").RelativeTo("a"),
                   Eigen::Matrix3d(RotationNumber(6).toRotationMatrix()), PositionNumber(6))));
  EXPECT_EQ(topology(), before);
  EXPECT_EQ(g.num_pose_edges(), edges);
  auto X_AC = g.GetPose(PoseSpec::Of("c").RelativeTo("a"));
  ASSERT_TRUE(X_AC);
  const Eigen::Isometry3d X_AC_expected = IsometryNumber(6) * IsometryNumber(5);
  EXPECT_TRUE(
      Near(TypeParam::ToMatrix(TypeParam::RotationOf(X_AC->value)), X_AC_expected.linear()));
  EXPECT_TRUE(Near(TypeParam::TranslationOf(X_AC->value), X_AC_expected.translation()));
  // A twist update too.
  ASSERT_TRUE(Accepts(g, AddScrewTwist(g, "b", "B", "A", 7)));
  auto V = g.GetTwist(TwistSpec::Of("b").RelativeTo("A").ExpressedIn("b"));
  ASSERT_TRUE(V);
  EXPECT_TRUE(Near(V->linear, LinearNumber(7)));
  EXPECT_TRUE(Near(V->angular, AngularNumber(7)));
  EXPECT_EQ(g.num_twist_edges(), 2u);
}

TYPED_TEST(SceneGraphConstraints, GraspRemovesTheObjectWrtTheTableAndAddsItWrtTheGripper) {
  auto& g = this->graph_;
  // Before and after the grasp:
  //
  //   {w}|World                     {w}|World
  //    +-- {t}|Table                 +-- {t}|Table
  //    |     +-- {o}|Object          +-- {g}|Gripper
  //    +-- {g}|Gripper                     +-- {o}|Object
  ASSERT_TRUE(Accepts(g, AddEdge(g, "t", "Table", "w", "World", 1)));
  ASSERT_TRUE(Accepts(g, AddEdge(g, "g", "Gripper", "w", "World", 2)));
  ASSERT_TRUE(Accepts(g, AddEdge(g, "o", "Object", "t", "Table", 3)));
  const Eigen::Isometry3d X_WO = IsometryNumber(1) * IsometryNumber(3);
  // A second parent is refused; the grasp is remove, then add.
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kMultiplePoseParents,
                              {"{o}|Object already has a pose parent {t}|Table"},
                              [&] { return AddEdge(g, "o", "Object", "g", "Gripper", 4); }));
  ASSERT_TRUE(Accepts(g, g.RemovePose("o", "t")));
  EXPECT_TRUE(QueryFails(g, g.GetPose(PoseSpec::Of("o").RelativeTo("w")),
                         PoseSpec::Of("o").RelativeTo("w"), ErrorCode::kNoPosePath));
  const Eigen::Isometry3d X_GO = IsometryNumber(2).inverse() * X_WO;  // where it was grasped
  ASSERT_TRUE(
      Accepts(g, g.AddPose(PoseSpec::Of("o", "Object").RelativeTo("g", "Gripper"),
                           Eigen::Matrix3d(X_GO.linear()), Eigen::Vector3d(X_GO.translation()))));
  EXPECT_EQ(g.frame_name(g.pose_parent(g.FindFrame("o"))), "g");
  auto X = g.GetPose(PoseSpec::Of("o").RelativeTo("w"));
  ASSERT_TRUE(X);
  EXPECT_TRUE(Near(TypeParam::ToMatrix(TypeParam::RotationOf(X->value)), X_WO.linear()));
  EXPECT_TRUE(Near(TypeParam::TranslationOf(X->value), X_WO.translation()));
  // The gripper moves; the object follows it, not the table.
  ASSERT_TRUE(Accepts(g, AddEdge(g, "g", "Gripper", "w", "World", 5)));
  X = g.GetPose(PoseSpec::Of("o").RelativeTo("w"));
  ASSERT_TRUE(X);
  EXPECT_TRUE(Near(TypeParam::TranslationOf(X->value), (IsometryNumber(5) * X_GO).translation()));
  auto p_TO = g.GetPosition(PoseSpec::Of("o").RelativeTo("t"));
  ASSERT_TRUE(p_TO);
  EXPECT_TRUE(
      Near(p_TO->value, (IsometryNumber(1).inverse() * IsometryNumber(5) * X_GO).translation()));
}

TYPED_TEST(SceneGraphConstraints, RemovingATwistEdgeRemovesItsTwistPathAndAllowsAnother) {
  auto& g = this->graph_;
  BuildTwoTrees(g);
  ASSERT_TRUE(Accepts(g, AddScrewTwist(g, "c", "C", "B", 2)));  // A ~> {b}, B ~> {c}
  ASSERT_TRUE(g.GetTwist(TwistSpec::Of("c").RelativeTo("A").ExpressedIn("c")));
  ASSERT_TRUE(Accepts(g, g.RemoveTwist("b", "A")));
  EXPECT_EQ(g.num_twist_edges(), 2u);
  EXPECT_FALSE(g.twist_parent(g.FindFrame("b")).is_valid());
  const TwistSpec c_wrt_a = TwistSpec::Of("c").RelativeTo("A").ExpressedIn("c");
  EXPECT_TRUE(QueryFails(g, g.GetTwist(c_wrt_a), c_wrt_a, ErrorCode::kNoTwistPath));
  EXPECT_TRUE(g.GetTwist(TwistSpec::Of("c").RelativeTo("B").ExpressedIn("c")));
  // C ~> {a} is legal now (it was a cycle before).
  EXPECT_TRUE(Accepts(g, AddScrewTwist(g, "a", "A", "C", 3)));
  auto V = g.GetTwist(TwistSpec::Of("a").RelativeTo("C").ExpressedIn("a"));
  ASSERT_TRUE(V);
  EXPECT_TRUE(Near(V->linear, LinearNumber(3)));
  // Removing a pose edge keeps the twists whose heads are in either part.
  ASSERT_TRUE(Accepts(g, g.RemovePose("b", "a")));
  EXPECT_EQ(g.num_twist_edges(), 3u);
  EXPECT_TRUE(g.GetTwist(TwistSpec::Of("c").RelativeTo("B").ExpressedIn("c")));
  EXPECT_TRUE(g.GetTwist(TwistSpec::Of("a").RelativeTo("C").ExpressedIn("a")));
}

// ====================================================================== homogeneous backend

// The homogeneous transform imposes point = origin of [a], ref point = origin of [b] and
// [r] = [b] on poses, and [r] = [b] on orientations (docs/rules.md §11); positions and twists are
// free.
//
// Fixture: BuildTwoTrees plus a second frame of C, {c} -> {c2}|C (constant).
class SceneGraphHomogeneous : public ::testing::Test {
 protected:
  void SetUp() override {
    BuildTwoTrees(graph_);
    ASSERT_TRUE(Accepts(graph_, AddEdge(graph_, "c2", "C", "c", "C", 5)));
  }
  SceneGraph<coord::HomogeneousBackend> graph_;
};

TEST_F(SceneGraphHomogeneous, RepresentationConstraintRejectsAddsInNonEdgeForm) {
  auto& g = graph_;
  const Eigen::Quaterniond q = RotationNumber(1);
  const Eigen::Vector3d p = PositionNumber(1);
  EXPECT_TRUE(RejectsAndKeeps(
      g, ErrorCode::kRepresentationConstraint,
      {"pose of (c2,[c])|C wrt {z}|Z", "homogeneous representation requires point c2|C",
       "to be the origin of orientation frame [c]|C"},
      [&] { return g.AddPose(PoseSpec::Of("c", "C").RelativeTo("z", "Z").AtPoint("c2"), q, p); }));
  EXPECT_TRUE(RejectsAndKeeps(
      g, ErrorCode::kRepresentationConstraint,
      {"homogeneous representation requires reference point"}, [&] {
        return g.AddPose(PoseSpec::Of("z", "Z").RelativeTo("c", "C").RelativeToPoint("c2"), q, p);
      }));
  EXPECT_TRUE(RejectsAndKeeps(
      g, ErrorCode::kRepresentationConstraint, {"in [a]", "homogeneous representation requires"},
      [&] {
        return g.AddPose(PoseSpec::Of("z", "Z").RelativeTo("c", "C").ExpressedIn("a"), q, p);
      }));
  // Also for an update of an existing edge.
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kRepresentationConstraint, {"homogeneous"}, [&] {
    return g.AddPose(PoseSpec::Of("c").RelativeTo("b").ExpressedIn("a"), q, p);
  }));
}

TEST_F(SceneGraphHomogeneous,
       RepresentationConstraintRejectsPoseQueriesWithAChangedPointRefPointOrFrame) {
  auto& g = graph_;
  ASSERT_TRUE(g.GetPose(PoseSpec::Of("c").RelativeTo("a")));
  for (PoseSpec s : {PoseSpec::Of("c").RelativeTo("a").AtPoint("c2"),
                     PoseSpec::Of("c").RelativeTo("a").RelativeToPoint("a2"),
                     PoseSpec::Of("c").RelativeTo("a").ExpressedIn("b")}) {
    EXPECT_TRUE(QueryFails(g, g.GetPose(s), s, ErrorCode::kRepresentationConstraint,
                           {"homogeneous representation requires"}));
  }
  // Orientation queries: [r] must be [b]; [a] anywhere in the tree is fine.
  const PoseSpec o = PoseSpec::Of("c").RelativeTo("a").ExpressedIn("b");
  EXPECT_TRUE(
      QueryFails(g, g.GetOrientation(o), o, ErrorCode::kRepresentationConstraint, {"homogeneous"}));
  EXPECT_TRUE(g.GetOrientation(PoseSpec::Of("c").RelativeTo("a2")));
  // Positions and twists are unconstrained.
  EXPECT_TRUE(g.GetPosition(PoseSpec::Of("c").RelativeTo("a").ExpressedIn("b")));
  EXPECT_TRUE(g.GetTwist(TwistSpec::Of("c", "B").RelativeTo("A").ExpressedIn("a2")));
}

TEST_F(SceneGraphHomogeneous,
       RepresentationConstraintComesAfterSelfEdgeAndBeforeConversionAndAfterNoPosePath) {
  auto& g = graph_;
  // self_edge before representation_constraint.
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kSelfEdge, {"to itself"}, [&] {
    return g.AddPose(PoseSpec::Of("c").RelativeTo("c").ExpressedIn("a"), RotationNumber(1),
                     PositionNumber(1));
  }));
  // representation_constraint before pose_not_convertible ([q] is not in the tree of {c}).
  EXPECT_TRUE(RejectsAndKeeps(g, ErrorCode::kRepresentationConstraint, {"homogeneous"}, [&] {
    return g.AddPose(PoseSpec::Of("z", "Z").RelativeTo("c", "C").ExpressedIn("q"),
                     RotationNumber(1), PositionNumber(1));
  }));
  // Queries: no_pose_path before representation_constraint.
  const PoseSpec s = PoseSpec::Of("c").RelativeTo("a").ExpressedIn("q");
  EXPECT_TRUE(QueryFails(g, g.GetPose(s), s, ErrorCode::kNoPosePath));
  EXPECT_TRUE(QueryFails(g, g.GetOrientation(s), s, ErrorCode::kNoPosePath));
}

TEST(SceneGraphQuaternion, AcceptsTheFormsTheHomogeneousBackendRejects) {
  SceneGraph<coord::QuaternionBackend> g;
  BuildTwoTrees(g);
  ASSERT_TRUE(Accepts(g, AddEdge(g, "c2", "C", "c", "C", 5)));
  EXPECT_TRUE(Accepts(g, g.AddPose(PoseSpec::Of("z", "Z").RelativeTo("c", "C").ExpressedIn("a"),
                                   RotationNumber(1), PositionNumber(1))));
  EXPECT_TRUE(g.GetPose(
      PoseSpec::Of("c").RelativeTo("a").AtPoint("c2").RelativeToPoint("a2").ExpressedIn("z")));
  EXPECT_TRUE(g.GetOrientation(PoseSpec::Of("c").RelativeTo("a").ExpressedIn("b")));
}

// Quaternion only: the homogeneous backend rejects every non-edge form first
// (representation_constraint, see SceneGraphHomogeneous).
TEST(SceneGraphQuaternion, PoseNotConvertibleRejectsPointsAndFramesOutsideTheTrees) {
  SceneGraph<coord::QuaternionBackend> g;
  BuildTwoTrees(g);
  ASSERT_TRUE(Accepts(g, AddEdge(g, "c2", "C", "x", "X")));  // a frame of C in another tree
  const auto add = [&](const PoseSpec& s) {
    return g.AddPose(s, RotationNumber(1), PositionNumber(1));
  };
  EXPECT_TRUE(RejectsAndKeeps(
      g, ErrorCode::kPoseNotConvertible, {"point c2 must be a frame of C in the pose tree of {c}"},
      [&] { return add(PoseSpec::Of("c", "C").RelativeTo("z", "Z").AtPoint("c2")); }));
  EXPECT_TRUE(RejectsAndKeeps(
      g, ErrorCode::kPoseNotConvertible,
      {"point c2 must be a frame of C in the pose tree of {new}"},
      [&] { return add(PoseSpec::Of("new", "C").RelativeTo("z", "Z").AtPoint("c2")); }));
  EXPECT_TRUE(RejectsAndKeeps(
      g, ErrorCode::kPoseNotConvertible,
      {"reference point c2 must be a frame of C in the pose tree of {c}"},
      [&] { return add(PoseSpec::Of("z", "Z").RelativeTo("c", "C").RelativeToPoint("c2")); }));
  EXPECT_TRUE(RejectsAndKeeps(
      g, ErrorCode::kPoseNotConvertible,
      {"coordinate frame [q] must be a frame in the pose tree of {c}"},
      [&] { return add(PoseSpec::Of("z", "Z").RelativeTo("c", "C").ExpressedIn("q")); }));
  EXPECT_TRUE(RejectsAndKeeps(
      g, ErrorCode::kPoseNotConvertible,
      {"coordinate frame [z] must be a frame in the pose tree of {c}"},
      [&] { return add(PoseSpec::Of("z", "Z").RelativeTo("c", "C").ExpressedIn("z")); }));
  // Inside the tree it is converted once to the edge {c} -> {z}; asked back in the same form,
  // the graph returns the numbers it was given.
  const PoseSpec in_a = PoseSpec::Of("z", "Z").RelativeTo("c", "C").ExpressedIn("a");
  ASSERT_TRUE(Accepts(g, add(in_a)));
  EXPECT_EQ(g.frame_name(g.pose_parent(g.FindFrame("z"))), "c");
  auto X_CZ_A = g.GetPose(in_a);
  ASSERT_TRUE(X_CZ_A);
  EXPECT_TRUE(
      Near(X_CZ_A->value.rotation.toRotationMatrix(), RotationNumber(1).toRotationMatrix()));
  EXPECT_TRUE(Near(X_CZ_A->value.translation, PositionNumber(1)));
}

}  // namespace
}  // namespace semgraph::core
