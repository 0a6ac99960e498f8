// `semgraph ellipses` (ellipse_writer.h): positions with their covariances as SVG ellipses.
#include "semgraph/ellipse_writer.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

namespace semgraph::script {

namespace {

std::string Num(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.17g", x);
  return buffer;
}

// Text content and attribute values: the five XML specials escaped.
std::string Xml(std::string_view text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// One frame's projected position and 1-sigma ellipse (scaled by sigma).
struct Ellipse {
  std::string name;
  double x = 0, y = 0;
  double major = 0, minor = 0, angle = 0;
};

// The semi-axes and the major axis's angle of the ellipse of a 2x2 covariance C (times sigma).
void Axes(const Eigen::Matrix2d& C, double sigma, Ellipse* e) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(0.5 * (C + C.transpose()));
  const Eigen::Vector2d lambda = eig.eigenvalues().cwiseMax(0.0);  // ascending
  e->major = sigma * std::sqrt(lambda(1));
  e->minor = sigma * std::sqrt(lambda(0));
  const Eigen::Vector2d v = eig.eigenvectors().col(1);
  double angle = std::atan2(v(1), v(0));  // an axis: fold into (-pi/2, pi/2]
  if (angle > std::numbers::pi / 2) angle -= std::numbers::pi;
  if (angle <= -std::numbers::pi / 2) angle += std::numbers::pi;
  e->angle = angle;
}

std::string Svg(const std::vector<Ellipse>& items, const EllipseOptions& options) {
  double lo_x = 0, hi_x = 0, lo_y = 0, hi_y = 0;
  for (const Ellipse& e : items) {
    lo_x = std::min(lo_x, e.x - e.major);
    hi_x = std::max(hi_x, e.x + e.major);
    lo_y = std::min(lo_y, e.y - e.major);
    hi_y = std::max(hi_y, e.y + e.major);
  }
  const double extent = std::max({hi_x - lo_x, hi_y - lo_y, 1e-9});
  const double scale = 600.0 / extent;  // pixels per metre; the drawing is at most 600 wide
  const double margin = 60.0;
  const double width = (hi_x - lo_x) * scale + 2 * margin;
  const double height = (hi_y - lo_y) * scale + 2 * margin;
  const auto sx = [&](double x) { return margin + (x - lo_x) * scale; };
  const auto sy = [&](double y) { return margin + (hi_y - y) * scale; };  // up is up
  static constexpr const char* kPlanes[] = {"xy", "xz", "yz"};
  std::string svg = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  svg += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + Num(width) + "\" height=\"" +
         Num(height) + "\" data-root=\"" + Xml(options.root) + "\" data-plane=\"" +
         kPlanes[static_cast<int>(options.plane)] + "\" data-sigma=\"" + Num(options.sigma) +
         "\" data-scale=\"" + Num(scale) + "\">\n";
  svg +=
      "  <title>" +
      Xml(std::string("positions relative to {") + options.root + "} with " + Num(options.sigma) +
          "-sigma ellipses, plane " + kPlanes[static_cast<int>(options.plane)]) +
      "</title>\n";
  for (const Ellipse& e : items) {
    const std::string cx = Num(sx(e.x)), cy = Num(sy(e.y));
    if (e.major > 0) {
      // SVG's y axis points down: a counter-clockwise angle in the plane is clockwise there.
      svg += "  <ellipse cx=\"" + cx + "\" cy=\"" + cy + "\" rx=\"" + Num(e.major * scale) +
             "\" ry=\"" + Num(e.minor * scale) + "\" transform=\"rotate(" +
             Num(-e.angle * 180.0 / std::numbers::pi) + " " + cx + " " + cy +
             ")\" fill=\"steelblue\" fill-opacity=\"0.25\" stroke=\"steelblue\" data-frame=\"" +
             Xml(e.name) + "\" data-x=\"" + Num(e.x) + "\" data-y=\"" + Num(e.y) +
             "\" data-major=\"" + Num(e.major) + "\" data-minor=\"" + Num(e.minor) +
             "\" data-angle=\"" + Num(e.angle) + "\"/>\n";
    }
    svg += "  <circle cx=\"" + cx + "\" cy=\"" + cy + "\" r=\"2\" fill=\"black\"/>\n";
    svg += "  <text x=\"" + Num(sx(e.x) + 5) + "\" y=\"" + Num(sy(e.y) - 5) +
           "\" font-family=\"sans-serif\" font-size=\"12\">{" + Xml(e.name) + "}</text>\n";
  }
  return svg + "</svg>\n";
}

}  // namespace

template <coord::Backend B>
base::Expected<std::string, std::string> WriteEllipses(const core::SceneGraph<B>& graph,
                                                       const EllipseOptions& options) {
  if (!(options.sigma > 0) || !std::isfinite(options.sigma)) {
    return base::Unexpected{std::string("--sigma must be a positive number")};
  }
  bool root_found = false;
  for (std::uint32_t i = 0; i < graph.num_frames(); ++i) {
    root_found = root_found || graph.frame_name(core::FrameIndex(i)) == options.root;
  }
  if (!root_found) {
    return base::Unexpected{"no frame named '" + options.root + "' in the scene"};
  }
  static constexpr int kAxes[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  const int* axes = kAxes[static_cast<int>(options.plane)];
  std::vector<Ellipse> items;
  for (std::uint32_t i = 0; i < graph.num_frames(); ++i) {
    const std::string name(graph.frame_name(core::FrameIndex(i)));
    const core::PoseSpec spec = core::PoseSpec::Of(name).RelativeTo(options.root);
    const auto r = graph.GetPositionWithCovariance(spec);
    if (!r) continue;  // another tree: no position relative to the root
    const Eigen::Vector3d p = r->value.value;
    Eigen::Matrix2d C;
    C << r->covariance(axes[0], axes[0]), r->covariance(axes[0], axes[1]),
        r->covariance(axes[1], axes[0]), r->covariance(axes[1], axes[1]);
    Ellipse e{name, p(axes[0]), p(axes[1])};
    Axes(C, options.sigma, &e);
    items.push_back(std::move(e));
  }
  return Svg(items, options);
}

template base::Expected<std::string, std::string> WriteEllipses(
    const core::SceneGraph<coord::QuaternionBackend>&, const EllipseOptions&);
template base::Expected<std::string, std::string> WriteEllipses(
    const core::SceneGraph<coord::HomogeneousBackend>&, const EllipseOptions&);

}  // namespace semgraph::script
