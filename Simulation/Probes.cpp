#include "Simulation/Probes.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "Utilities/Error.h"
#include "Utilities/ParallelFor.h"
#include "Utilities/Text.h"

namespace consph {

std::vector<ProbeDescription> parseProbes(const json& probes, const LogSink& log) {
  std::vector<ProbeDescription> out;
  if (probes.is_null()) return out;
  if (!probes.is_array()) throw InputError("probes: expected an array of probe objects");
  std::set<std::string> names;
  for (std::size_t i = 0; i < probes.size(); ++i) {
    const std::string path = "probes[" + std::to_string(i) + "]";
    if (!probes[i].is_object()) throw InputError(path + ": expected an object");
    const json& kindValue = probes[i].contains("kind") ? probes[i]["kind"] : json();
    if (!kindValue.is_string()) throw InputError(path + ".kind: required string is missing (pressure, level or force)");
    const std::string kind = kindValue.get<std::string>();
    ProbeDescription d;
    d.path = path;
    std::vector<ParamSpec> specs{{"name", ParamType::String, json(), "column name in probes.csv"}};
    if (kind == "pressure") {
      d.kind = ProbeKind::Pressure;
      specs.push_back({"position", ParamType::Vector3, json(), "a point on a static boundary surface, m"});
      specs.push_back({"radius", ParamType::Real, 0.0, "radius of the averaging disc, m (0: twice the kernel support)", 0, 1e6});
    } else if (kind == "level") {
      d.kind = ProbeKind::Level;
      specs.push_back({"position", ParamType::Vector3, json(), "the gauge's base: a point of the vertical line, m"});
    } else if (kind == "force") {
      d.kind = ProbeKind::Force;
      specs.push_back({"boundary", ParamType::String, json(), "name of the boundary object"});
      specs.push_back({"point", ParamType::Vector3, json::array({0, 0, 0}),
                       "torque reference, m (default: a static object's bounding-box centre, a moving body's centre of mass)"});
    } else {
      throw InputError(path + ".kind: unknown probe kind '" + kind + "'; valid are: force, level, pressure");
    }
    // "region" only for force probes: on the others it is an unknown key, warned about.
    Params p(probes[i], path, specs, log, d.kind == ProbeKind::Force ? std::vector<std::string>{"kind", "region"} : std::vector<std::string>{"kind"});
    d.name = p.string("name");
    if (d.name.empty()) throw InputError(p.pathOf("name") + ": must not be empty");
    if (!printableUtf8(d.name) || d.name.find_first_of(",\"") != std::string::npos)
      throw InputError(p.pathOf("name") + ": must be printable UTF-8 text without a comma or a quote (it is a CSV column)");
    if (!names.insert(d.name).second) throw InputError(p.pathOf("name") + ": another probe is already named '" + d.name + "'");
    if (d.kind == ProbeKind::Force) {
      d.boundary = p.string("boundary");
      d.hasPoint = p.isSet("point");
      d.point = p.vector3("point");
      if (probes[i].contains("region")) {
        Params region(probes[i]["region"], p.pathOf("region"),
                      {{"min", ParamType::Vector3, json(), "lower corner, m"}, {"max", ParamType::Vector3, json(), "upper corner, m"}},
                      log, {});
        d.hasRegion = true;
        d.regionMin = region.vector3("min");
        d.regionMax = region.vector3("max");
        if ((d.regionMax - d.regionMin).minCoeff() <= 0) throw InputError(p.pathOf("region") + ": max must exceed min on every axis");
      }
    } else {
      d.position = p.vector3("position");
      if (d.kind == ProbeKind::Pressure) d.radius = p.real("radius");
    }
    out.push_back(std::move(d));
  }
  return out;
}

namespace {

Vector3r triangleNormal(const TriangleMesh& mesh, std::size_t t) {
  const auto& tri = mesh.triangles[t];
  const Vector3r& a = mesh.vertices[tri[0]];
  return (mesh.vertices[tri[1]] - a).cross(mesh.vertices[tri[2]] - a);
}

// The point of `mesh` closest to x among triangles whose unit normal n_t has n_t . facing >
// minCos (all when `facing` is zero); its triangle in `triangle`. Infinite when none qualifies.
Vector3r closestPointOnMesh(const TriangleMesh& mesh, const Vector3r& x, const Vector3r& facing, Real minCos,
                            std::size_t& triangle) {
  Real best = std::numeric_limits<Real>::infinity();
  Vector3r bestPoint = Vector3r::Constant(best);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Vector3r n = triangleNormal(mesh, t);
    const Real length = n.norm();
    if (length <= 0) continue;
    if (!facing.isZero() && n.dot(facing) <= minCos * length) continue;
    const auto& tri = mesh.triangles[t];
    const Vector3r q = closestPointOnTriangle(x, mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]]);
    const Real d = (q - x).squaredNorm();
    if (d < best) {
      best = d;
      bestPoint = q;
      triangle = t;
    }
  }
  return bestPoint;
}

}  // namespace

Probes::Probes(std::vector<ProbeDescription> probes, const std::vector<BoundaryObject>& objects, Real supportRadius,
               const Vector3r& gravity)
    : probes_(std::move(probes)), supportRadius_(supportRadius) {
  if (gravity.norm() > 0) up_ = -gravity.normalized();
  objectCentre_.resize(objects.size());
  for (std::size_t o = 0; o < objects.size(); ++o) {
    Vector3r lo, hi;
    objects[o].mesh.boundingBox(lo, hi);
    objectCentre_[o] = Real(0.5) * (lo + hi);
  }
  pressure_.resize(probes_.size());
  forceObject_.assign(probes_.size(), Index(0));
  for (std::size_t p = 0; p < probes_.size(); ++p) {
    const ProbeDescription& d = probes_[p];
    column_.push_back(Index(columns_.size()));
    if (d.kind == ProbeKind::Force) {
      for (const char* c : {".fx", ".fy", ".fz", ".tx", ".ty", ".tz"}) columns_.push_back(d.name + c);
      std::size_t o = 0;
      while (o < objects.size() && objects[o].name != d.boundary) ++o;
      if (o == objects.size()) {
        std::string known;
        for (const BoundaryObject& b : objects) known += (known.empty() ? "" : ", ") + (b.name.empty() ? "(unnamed)" : b.name);
        throw InputError(d.path + ".boundary: no boundary object is named '" + d.boundary + "' (named: " +
                         (known.empty() ? "none" : known) + ")");
      }
      forceObject_[p] = Index(o);
      readsLoads_ = true;
      continue;
    }
    columns_.push_back(d.name);
    if (d.kind == ProbeKind::Level) continue;
    readsLoads_ = true;
    // Pressure: the nearest static surface, within one kernel support of the given position.
    PressureGeometry& g = pressure_[p];
    Real nearest = std::numeric_limits<Real>::infinity();
    std::size_t triangle = 0;
    for (std::size_t o = 0; o < objects.size(); ++o) {
      if (objects[o].motion != BodyMotion::Static) continue;
      std::size_t t = 0;
      const Vector3r q = closestPointOnMesh(objects[o].mesh, d.position, Vector3r::Zero(), 0, t);
      if ((q - d.position).norm() < nearest) {
        nearest = (q - d.position).norm();
        g.object = o;
        g.centre = q;
        triangle = t;
      }
    }
    if (!(nearest <= supportRadius))
      throw InputError(d.path + ".position: not on a static boundary surface (the nearest is " +
                       (std::isfinite(nearest) ? std::to_string(nearest) + " m away" : std::string("missing")) +
                       "; a pressure probe must lie within one kernel support of one)");
    const TriangleMesh& mesh = objects[g.object].mesh;
    // Winding normals point away from a body's solid and, for a container (whose triangles were
    // flipped when loaded), into it: towards the fluid either way.
    g.normal = triangleNormal(mesh, triangle).normalized();
    g.radius = d.radius > 0 ? d.radius : 2 * supportRadius;
    // int w dA over the object's surface facing the probe: a grid of the disc in the tangent
    // plane, a cell counted where the surface lies along the normal through it (its projected area).
    const Vector3r t1 = g.normal.unitOrthogonal(), t2 = g.normal.cross(t1);
    const int cells = 32;
    const Real h = g.radius / cells;
    double area = 0;
    for (int a = -cells; a < cells; ++a)
      for (int b = -cells; b < cells; ++b) {
        const Real u = (a + Real(0.5)) * h, v = (b + Real(0.5)) * h;
        const Real t2sq = u * u + v * v;
        if (t2sq >= g.radius * g.radius) continue;
        const Vector3r x = g.centre + u * t1 + v * t2;
        std::size_t t = 0;
        const Vector3r q = closestPointOnMesh(mesh, x, g.normal, Real(0.5), t);
        const Vector3r offset = q - x;
        if ((offset - offset.dot(g.normal) * g.normal).norm() < Real(0.5) * h && std::abs(offset.dot(g.normal)) < g.radius)
          area += weight(t2sq, g.radius) * h * h;
      }
    g.weightedArea = Real(area);
  }
  values_.assign(columns_.size(), 0.0);
}

Real Probes::weight(Real t2, Real radius) const {
  const Real s = Real(1) - t2 / (radius * radius);
  return s > 0 ? s * s : Real(0);
}

void Probes::setObjectCentre(std::size_t object, const Vector3r& centre) { objectCentre_[object] = centre; }

void Probes::measureLoads(const NeighborLists& lists, const std::vector<Vector3r>& fluidPositions,
                          const BoundaryModel& boundary, const std::vector<Vector3r>& impulses, Real dt) {
  if (!readsLoads_) return;
  const BoundarySamples& samples = boundary.samples();
  // Accumulators: per probe, 6 slots (pressure probes use the first), summed over the pairs of
  // every fluid particle in parallel (one array per thread, joined after the loop: no atomics).
  const std::size_t np = probes_.size();
  const Real h = supportRadius_;
  auto join = [](std::vector<double>& into, const std::vector<double>& from) {
    for (std::size_t s = 0; s < into.size(); ++s) into[s] += from[s];
  };
  const std::vector<double> zeros(6 * np, 0.0);
  const std::vector<double> sums = parallelReduce(lists.queryCount(), zeros, join, [&](std::size_t i, std::vector<double>& threadSums) {
    double* acc = threadSums.data();
    for (Index e = lists.begin(i); e < lists.end(i); ++e) {
      const Index k = lists.indices[e];
      const Index object = samples.bodies[k];
      const Vector3r& J = impulses[e];
      for (std::size_t p = 0; p < np; ++p) {
        const ProbeDescription& d = probes_[p];
        if (d.kind == ProbeKind::Force) {
          if (forceObject_[p] != object) continue;
          const Vector3r load = d.hasRegion ? boundary.impulseInBox(k, fluidPositions[i], J, d.regionMin, d.regionMax) : J;
          const Vector3r reference = d.hasPoint ? d.point : objectCentre_[object];
          const Vector3r torque = (fluidPositions[i] - reference).cross(load);
          for (int a = 0; a < 3; ++a) acc[6 * p + a] += load[a], acc[6 * p + 3 + a] += torque[a];
        } else if (d.kind == ProbeKind::Pressure) {
          const PressureGeometry& g = pressure_[p];
          if (g.object != object) continue;
          const Vector3r r = samples.positions[k] - g.centre;
          const Real normal = r.dot(g.normal);
          if (std::abs(normal) >= h) continue;
          const Real t2 = r.squaredNorm() - normal * normal;
          if (t2 >= g.radius * g.radius) continue;
          acc[6 * p] += weight(t2, g.radius) * -J.dot(g.normal);  // the fluid pushes the wall along -n
        }
      }
    }
  });
  for (std::size_t p = 0; p < np; ++p) {
    const ProbeDescription& d = probes_[p];
    if (d.kind == ProbeKind::Force)
      for (int a = 0; a < 6; ++a) values_[column_[p] + a] = sums[6 * p + a] / dt;
    else if (d.kind == ProbeKind::Pressure)
      values_[column_[p]] = pressure_[p].weightedArea > 0 ? sums[6 * p] / (dt * pressure_[p].weightedArea) : 0.0;
  }
  // The window since the last row: each load's impulse (value x dt) and the time it spans.
  window_.impulses.resize(values_.size(), 0.0);
  for (std::size_t p = 0; p < np; ++p)
    for (std::size_t a = 0; a < loadColumns(p); ++a) window_.impulses[column_[p] + a] += values_[column_[p] + a] * double(dt);
  window_.time += double(dt);
  ++window_.steps;
}

std::vector<double> Probes::windowValues() const {
  // One step in the window: its values as they are (every-step rows keep their bits).
  std::vector<double> out = values_;
  if (window_.steps <= 1 || !(window_.time > 0)) return out;
  for (std::size_t p = 0; p < probes_.size(); ++p)
    for (std::size_t a = 0; a < loadColumns(p); ++a) out[column_[p] + a] = window_.impulses[column_[p] + a] / window_.time;
  return out;
}

void Probes::startWindow() {
  std::fill(window_.impulses.begin(), window_.impulses.end(), 0.0);
  window_.time = 0;
  window_.steps = 0;
}

void Probes::measureLevels(const FluidModel& fluid, const CubicSplineKernel& kernel) {
  const Real h = kernel.supportRadius();
  for (std::size_t p = 0; p < probes_.size(); ++p) {
    const ProbeDescription& d = probes_[p];
    if (d.kind != ProbeKind::Level) continue;
    // The particles within h of the line, as (height above the base, position).
    std::vector<Index> near;
    Real top = 0;
    for (std::size_t j = 0; j < fluid.size(); ++j) {
      const Vector3r r = fluid.positions[j] - d.position;
      const Real s = r.dot(up_);
      if ((r - s * up_).squaredNorm() >= h * h || s <= -h) continue;
      near.push_back(Index(j));
      top = std::max(top, s + h);
    }
    auto colour = [&](Real s) {
      const Vector3r x = d.position + s * up_;
      Real c = 0;
      for (Index j : near) c += fluid.masses[j] / fluid.densities[j] * kernel.W(x - fluid.positions[j]);
      return c;
    };
    // From above the highest particle down in steps of h / 16, then bisection to h / 1000.
    const Real step = h / 16;
    Real level = 0;
    for (Real s = top; s > 0; s -= step) {
      if (colour(s) < Real(0.5)) continue;
      Real lo = s, hi = s + step;  // c(lo) >= 1/2 > c(hi)
      while (hi - lo > h / 1000) {
        const Real mid = Real(0.5) * (lo + hi);
        (colour(mid) >= Real(0.5) ? lo : hi) = mid;
      }
      level = Real(0.5) * (lo + hi);
      break;
    }
    values_[column_[p]] = d.position.dot(up_) + level;
  }
}

json Probes::latest() const {
  json out = json::object();
  for (std::size_t c = 0; c < columns_.size(); ++c) out[columns_[c]] = values_[c];
  return out;
}

}  // namespace consph
