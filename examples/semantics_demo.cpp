// semgraph_demo: what the semantic checks of semgraph do, on names only (no numbers yet).
//
// The scene is the example of De Laet et al., IROS 2013: a robot base B with frame {b}, an end
// effector E {e}, an object O1 with frame {o1} and a feature frame {f1}, a spray gun O2 {o2}
// and a camera C {c}. A pose is written PoseCoord({a}|A, {b}|B, [r]): the pose of frame {a}
// on body A relative to frame {b} on body B, with its numbers expressed in the axes [r].
#include <cstdlib>
#include <iostream>
#include <string_view>

#include "semgraph/semantics/describe.h"
#include "semgraph/semantics/names.h"
#include "semgraph/semantics/operations.h"
#include "semgraph/semantics/relations.h"

namespace sem = semgraph::semantics;

namespace {

sem::NameTable names;  // every name is interned once; the checks then compare small ids

sem::NameId Intern(std::string_view name) {
  auto id = names.Intern(name);
  if (!id) {
    std::cerr << "cannot intern '" << name << "': " << sem::Describe(id.error(), name) << "\n";
    std::exit(1);
  }
  return *id;
}

std::string Show(const sem::PoseSemantics& s) { return sem::Describe(s, names); }
std::string Show(const sem::OrientationSemantics& s) { return sem::Describe(s, names); }

// The result of an operation that must succeed (it does, for the relations of this demo).
template <class T>
T Must(const sem::Checked<T>& result) {
  if (!result) {
    std::cerr << "unexpected: " << sem::Describe(result.error(), names) << "\n";
    std::exit(1);
  }
  return *result;
}

// Prints why an operation was refused; returns false if it was wrongly accepted.
template <class T>
bool Rejected(const sem::Checked<T>& result) {
  if (result) {
    std::cout << "  ERROR: accepted\n";
    return false;
  }
  std::cout << "  rejected (" << semgraph::base::ToString(result.error().code)
            << "): " << sem::Describe(result.error(), names) << "\n";
  return true;
}

}  // namespace

int main() {
  // Bodies and the frames fixed to them.
  const sem::Body B(Intern("B")), E(Intern("E")), O1(Intern("O1")), O2(Intern("O2")),
      C(Intern("C"));
  const sem::Frame b(Intern("b")), e(Intern("e")), o1(Intern("o1")), o2(Intern("o2")),
      f1(Intern("f1")), c(Intern("c"));
  std::cout << "Interned " << names.size()
            << " names: bodies B E O1 O2 C, frames b e o1 o2 f1 c\n\n";

  // The known relations, each expressed in its reference frame (the scene-graph edge form).
  const auto f1_wrt_o1 = sem::PoseSemantics::OfFrame(f1, O1, o1, O1, o1.axes());
  const auto o1_wrt_c = sem::PoseSemantics::OfFrame(o1, O1, c, C, c.axes());
  const auto c_wrt_b = sem::PoseSemantics::OfFrame(c, C, b, B, b.axes());
  const auto o2_wrt_e = sem::PoseSemantics::OfFrame(o2, O2, e, E, e.axes());
  std::cout << "Known poses:\n"
            << "  feature on the object  " << Show(f1_wrt_o1) << "\n"
            << "  object seen by camera  " << Show(o1_wrt_c) << "\n"
            << "  camera on the base     " << Show(c_wrt_b) << "\n"
            << "  spray gun in gripper   " << Show(o2_wrt_e) << "  (not used below)\n\n";

  // Compose in natural order: (f1 wrt o1) then (o1 wrt c) gives f1 wrt c. Checked: the
  // reference of the first (point o1, axes [o1], body O1) is what the second is the pose of.
  std::cout << "compose: the reference frame of the first must be the frame the second is about\n";
  const auto f1_wrt_c = Must(sem::Compose(f1_wrt_o1, o1_wrt_c)).result;
  const auto f1_wrt_b = Must(sem::Compose(f1_wrt_c, c_wrt_b)).result;
  std::cout << "  " << Show(f1_wrt_o1) << " o " << Show(o1_wrt_c) << "\n"
            << "    = " << Show(f1_wrt_c) << "\n"
            << "  " << Show(f1_wrt_c) << " o " << Show(c_wrt_b) << "\n"
            << "    = " << Show(f1_wrt_b) << "\n"
            << "  (each operand in its own reference frame: the matrix chain form)\n\n";

  // Inverse re-expressed in the new reference frame: the base as seen from the camera.
  // Checked: the pose must be expressed in its own reference frame [b].
  std::cout << "inverse_in_new_ref: the pose must be expressed in its reference frame\n";
  const auto b_wrt_c = Must(sem::InverseInNewRef(c_wrt_b));
  std::cout << "  " << Show(c_wrt_b) << "  ->  " << Show(b_wrt_c) << "\n\n";

  // Change of coordinate frame: the same pose of f1 wrt b, its numbers now expressed in the
  // camera axes [c]. The argument is the orientation of the old axes [b] wrt the new axes [c].
  std::cout << "change_coordinate_frame: needs the orientation of the old axes wrt the new ones\n";
  const auto b_axes_wrt_c = sem::OrientationOf(b_wrt_c);
  const auto f1_wrt_b_in_c = Must(sem::ChangeCoordinateFrame(f1_wrt_b, b_axes_wrt_c));
  std::cout << "  " << Show(f1_wrt_b) << " with " << Show(b_axes_wrt_c) << "\n"
            << "    = " << Show(f1_wrt_b_in_c) << "\n\n";

  // Wrong operations are refused, with a message naming the fields that do not match.
  std::cout << "Wrong operations are rejected before any number is computed:\n";
  bool ok = true;
  std::cout << "- compose " << Show(f1_wrt_o1) << " with " << Show(c_wrt_b) << "\n";
  ok &= Rejected(sem::Compose(f1_wrt_o1, c_wrt_b));

  const auto c_axes_wrt_b = sem::OrientationOf(c_wrt_b);
  std::cout << "- change_coordinate_frame of " << Show(f1_wrt_b) << " with " << Show(c_axes_wrt_b)
            << " (the orientation the wrong way round)\n";
  ok &= Rejected(sem::ChangeCoordinateFrame(f1_wrt_b, c_axes_wrt_b));

  std::cout << "- inverse_in_new_ref of " << Show(f1_wrt_b_in_c)
            << " (not expressed in its reference frame)\n";
  ok &= Rejected(sem::InverseInNewRef(f1_wrt_b_in_c));

  return ok ? 0 : 1;
}
