#include "io/pictures/VtkWriter.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "core/elements/EulerParameters.hpp"
#include "io/formats/TextOutput.hpp"

namespace flexmb::io {

namespace {
std::string n17(double v) { return shortNumber(v, 17); }

void checkFinite(const Eigen::VectorXd& v, const char* what, double t, Eigen::Index expected) {
  if (v.size() != expected)
    throw std::invalid_argument(std::string("VTK output: ") + what + " has " + std::to_string(v.size()) +
                                " entries, the model has " + std::to_string(expected));
  for (Eigen::Index i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]))
      throw std::invalid_argument(std::string("VTK output: ") + what + "(" + std::to_string(i + 1) +
                                  ") is not finite at t = " + shortNumber(t, 10));
}

// Per sampled point the rotation from the initial configuration as a rotation vector (axis times
// angle, rad): the section frame of a framed element's point, else the orientation node attached at
// the point's position node (planar: about z), else zero.
std::vector<Point3> pointRotations(const MechanismGeometry& g, const Eigen::VectorXd& x) {
  const core::Model& m = g.model();
  std::vector<Point3> rot(g.numPoints()), y, z, y0, z0;
  g.sectionAxes(x, y, z);
  g.sectionAxes(m.x0, y0, z0);
  std::vector<int> orientationAt(m.nodes.size(), -1);
  for (size_t n = 0; n < m.nodes.size(); ++n)
    if (!g.isPositionNode(static_cast<int>(n)) && g.anchor(static_cast<int>(n)) >= 0 &&
        orientationAt[g.anchor(static_cast<int>(n))] < 0)
      orientationAt[g.anchor(static_cast<int>(n))] = static_cast<int>(n);
  auto v = [](const Point3& p) { return Eigen::Vector3d(p.x, p.y, p.z); };
  auto frame = [&](const Point3& a, const Point3& b) {
    Eigen::Matrix3d F;
    F.col(1) = v(a), F.col(2) = v(b), F.col(0) = v(a).cross(v(b));
    return F;
  };
  auto rotationVector = [](const Eigen::Matrix3d& R) {
    const Eigen::AngleAxisd aa(R);
    const Eigen::Vector3d r = aa.angle() * aa.axis();
    return Point3{r[0], r[1], r[2]};
  };
  for (int i = 0; i < g.numPoints(); ++i) {
    if (v(y[i]).squaredNorm() > 0.5 && v(y0[i]).squaredNorm() > 0.5) {
      rot[i] = rotationVector(frame(y[i], z[i]) * frame(y0[i], z0[i]).transpose());
      continue;
    }
    const int node = g.pointNodes()[i];
    const int o = node >= 0 ? orientationAt[node] : -1;
    if (o < 0) continue;
    const core::Node& n = m.nodes[o];
    if (n.kind == core::NodeKind::Orientation) {
      rot[i] = {0.0, 0.0, x[n.firstCoord] - m.x0[n.firstCoord]};
    } else if (n.kind == core::NodeKind::EulerParameters) {
      const Eigen::Vector4d l = x.segment<4>(n.firstCoord), l0 = m.x0.segment<4>(n.firstCoord);
      if (l.norm() > 0 && l0.norm() > 0)
        rot[i] =
            rotationVector(core::euler::rotation(l.normalized()) * core::euler::rotation(l0.normalized()).transpose());
    }
  }
  return rot;
}

int maxDeformations(const core::Model& m) {
  int k = 1;
  for (const auto& el : m.elements) k = std::max(k, el.type->numDeformations());
  return k;
}
}  // namespace

std::string renderVtu(const MechanismGeometry& g, const core::StateOutputs& s, double t) {
  const core::Model& m = g.model();
  checkFinite(s.x, "x", t, m.nx);
  checkFinite(s.e, "e", t, m.ne);
  checkFinite(s.ed, "ed", t, m.ne);
  checkFinite(s.sig, "sig", t, m.ne);
  std::vector<Point3> p, p0;
  g.points(s.x, p);
  g.points(m.x0, p0);
  const int nc = maxDeformations(m);
  const auto& cells = g.elements();

  std::string o;
  o.reserve(4096 + 120 * p.size());
  o += "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
       "<UnstructuredGrid>\n<FieldData>\n<DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" "
       "format=\"ascii\">" +
       n17(t) + "</DataArray>\n</FieldData>\n";
  o += "<Piece NumberOfPoints=\"" + std::to_string(p.size()) + "\" NumberOfCells=\"" + std::to_string(cells.size()) +
       "\">\n";
  o += "<Points>\n<DataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const Point3& q : p) o += n17(q.x) + " " + n17(q.y) + " " + n17(q.z) + "\n";
  o += "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const DrawnElement& d : cells) {
    for (int k = 0; k < d.numPoints; ++k) o += std::to_string(d.firstPoint + k) + (k + 1 < d.numPoints ? " " : "");
    o += "\n";
  }
  o += "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (const DrawnElement& d : cells) o += std::to_string(d.firstPoint + d.numPoints) + " ";
  o += "\n</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (const DrawnElement& d : cells) o += d.shape == DrawnShape::Joint ? "1 " : "4 ";
  o += "\n</DataArray>\n</Cells>\n";

  o += "<PointData Vectors=\"displacement\">\n<DataArray type=\"Float64\" Name=\"displacement\" "
       "NumberOfComponents=\"3\" "
       "format=\"ascii\">\n";
  for (size_t i = 0; i < p.size(); ++i)
    o += n17(p[i].x - p0[i].x) + " " + n17(p[i].y - p0[i].y) + " " + n17(p[i].z - p0[i].z) + "\n";
  o += "</DataArray>\n<DataArray type=\"Float64\" Name=\"rotation\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const Point3& r : pointRotations(g, s.x)) o += n17(r.x) + " " + n17(r.y) + " " + n17(r.z) + "\n";
  o += "</DataArray>\n<DataArray type=\"Int32\" Name=\"node_label\" format=\"ascii\">\n";
  for (int n : g.pointNodes()) o += std::to_string(n >= 0 ? m.nodes[n].label : 0) + " ";
  o += "\n</DataArray>\n</PointData>\n<CellData Scalars=\"element_label\">\n";
  o += "<DataArray type=\"Int32\" Name=\"element_label\" format=\"ascii\">\n";
  for (const DrawnElement& d : cells) o += std::to_string(m.elements[d.element].label) + " ";
  o += "\n</DataArray>\n";
  auto perElement = [&](const char* name, const Eigen::VectorXd& v) {
    o += std::string("<DataArray type=\"Float64\" Name=\"") + name + "\" NumberOfComponents=\"" + std::to_string(nc) +
         "\" format=\"ascii\">\n";
    for (const DrawnElement& d : cells) {
      const core::ElementEntry& el = m.elements[d.element];
      for (int k = 0; k < nc; ++k)
        o += (k < el.type->numDeformations() ? n17(v[el.firstDef + k]) : std::string("0")) + (k + 1 < nc ? " " : "\n");
    }
    o += "</DataArray>\n";
  };
  perElement("deformation", s.e);
  perElement("deformation_rate", s.ed);
  perElement("stress", s.sig);
  o += "</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  return o;
}

std::vector<std::string> writeVtkSeries(const std::string& prefix, const core::Model& model,
                                        const core::Trajectory& traj) {
  if (traj.states.size() != traj.time.size())
    throw std::invalid_argument("VTK output: " + std::to_string(traj.time.size()) + " times but " +
                                std::to_string(traj.states.size()) + " states");
  namespace fs = std::filesystem;
  const fs::path pvd = prefix + ".pvd";
  const std::string stem = pvd.stem().string();
  const fs::path folderName = stem + "_vtu";
  const fs::path folder = pvd.parent_path() / folderName;
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) throw std::runtime_error("cannot create the folder '" + folder.string() + "': " + ec.message());

  const MechanismGeometry g(model);
  std::vector<std::string> written{pvd.string()};
  std::string collection =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" "
      "byte_order=\"LittleEndian\">\n<Collection>\n";
  const int digits = std::max<int>(5, static_cast<int>(std::to_string(traj.time.size()).size()));
  for (size_t k = 0; k < traj.time.size(); ++k) {
    std::string index = std::to_string(k);
    index.insert(0, static_cast<size_t>(std::max(0, digits - static_cast<int>(index.size()))), '0');
    const fs::path name = folderName / (stem + "_" + index + ".vtu");
    const fs::path file = pvd.parent_path() / name;
    writeTextFile(file.string(), renderVtu(g, traj.states[k], traj.time[k]));
    written.push_back(file.string());
    collection += "<DataSet timestep=\"" + n17(traj.time[k]) + "\" group=\"\" part=\"0\" file=\"" +
                  xmlEscape(name.generic_string()) + "\"/>\n";
  }
  collection += "</Collection>\n</VTKFile>\n";
  writeTextFile(pvd.string(), collection);
  // The collection is written last: a .pvd on disk means its series is complete.
  return written;
}

}  // namespace flexmb::io
