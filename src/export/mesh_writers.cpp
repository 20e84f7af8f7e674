#include "export/mesh_writers.h"

#include <cstdint>
#include <cstdio>
#include <cstring>

namespace clothsim {
namespace {

// Every target clothsim builds for is little-endian (x86-64, aarch64): the bytes as they are.
static_assert(sizeof(float) == 4 && sizeof(std::int32_t) == 4);
template <typename T>
void put(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

void put_number(std::string& out, double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", value);
  out += text;
}

std::size_t vertex_count(const MeshPart& part) { return part.points.size() / 3; }

const char* const kAxes[3] = {"x", "y", "z"};

// A file name inside an XML attribute: the five characters XML reserves, escaped.
std::string xml_attribute(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace

std::string obj_text(const MeshPart& part, const std::string& comment) {
  std::string out = "# " + comment + "\no " + part.name + "\n";
  for (std::size_t i = 0; i < vertex_count(part); ++i) {
    out += "v";
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      put_number(out, part.points[3 * i + static_cast<std::size_t>(k)]);
    }
    out += '\n';
  }
  for (std::size_t t = 0; t + 2 < part.triangles.size(); t += 3)
    out += "f " + std::to_string(part.triangles[t] + 1) + " " + std::to_string(part.triangles[t + 1] + 1) + " " +
           std::to_string(part.triangles[t + 2] + 1) + "\n";
  return out;
}

std::string ply_bytes(const MeshPart& part, const std::string& comment) {
  const std::size_t n = vertex_count(part);
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment " + comment + "\nelement vertex " +
                    std::to_string(n) + "\nproperty float x\nproperty float y\nproperty float z\n";
  for (const VertexField& f : part.fields)
    for (int k = 0; k < f.components; ++k)
      out += "property float " + (f.components == 1 ? f.name : std::string(1, f.name[0]) + kAxes[k]) + "\n";
  out += "element face " + std::to_string(part.triangles.size() / 3) +
         "\nproperty list uchar int vertex_indices\nend_header\n";
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) put(out, part.points[3 * i + static_cast<std::size_t>(k)]);
    for (const VertexField& f : part.fields)
      for (int k = 0; k < f.components; ++k)
        put(out, f.values[static_cast<std::size_t>(f.components) * i + static_cast<std::size_t>(k)]);
  }
  for (std::size_t t = 0; t + 2 < part.triangles.size(); t += 3) {
    put(out, static_cast<std::uint8_t>(3));
    for (int k = 0; k < 3; ++k) put(out, static_cast<std::int32_t>(part.triangles[t + static_cast<std::size_t>(k)]));
  }
  return out;
}

std::string vtp_text(const MeshPart& part) {
  const std::size_t n = vertex_count(part), triangles = part.triangles.size() / 3;
  std::string out =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "<PolyData>\n<Piece NumberOfPoints=\"" + std::to_string(n) +
      "\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"" +
      std::to_string(triangles) + "\">\n<PointData>\n";
  const auto array = [&out](const std::string& attributes, const std::vector<float>& values) {
    out += "<DataArray type=\"Float32\" " + attributes + " format=\"ascii\">\n";
    for (float v : values) {
      put_number(out, v);
      out += ' ';
    }
    out += "\n</DataArray>\n";
  };
  for (const VertexField& f : part.fields)
    array("Name=\"" + f.name + "\" NumberOfComponents=\"" + std::to_string(f.components) + "\"", f.values);
  out += "</PointData>\n<Points>\n";
  array("Name=\"Points\" NumberOfComponents=\"3\"", part.points);
  out += "</Points>\n<Polys>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n";
  for (std::uint32_t i : part.triangles) out += std::to_string(i) + ' ';
  out += "\n</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n";
  for (std::size_t t = 1; t <= triangles; ++t) out += std::to_string(3 * t) + ' ';
  out += "\n</DataArray>\n</Polys>\n</Piece>\n</PolyData>\n</VTKFile>\n";
  return out;
}

std::string pc2_header(int points, float start_frame, float sample_rate, int samples) {
  std::string out("POINTCACHE2", 12);  // with its terminating NUL
  put(out, static_cast<std::int32_t>(1));
  put(out, static_cast<std::int32_t>(points));
  put(out, start_frame);
  put(out, sample_rate);
  put(out, static_cast<std::int32_t>(samples));
  return out;
}

std::string pc2_sample(const MeshPart& part) {
  std::string out;
  out.reserve(4 * part.points.size());
  for (float v : part.points) put(out, v);
  return out;
}

std::string pvd_text(const std::vector<PvdEntry>& entries) {
  std::string out =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "<Collection>\n";
  for (const PvdEntry& e : entries) {
    char t[32];
    std::snprintf(t, sizeof t, "%.17g", e.t);
    out += "<DataSet timestep=\"" + std::string(t) + "\" group=\"\" part=\"" + std::to_string(e.part) +
           "\" file=\"" + xml_attribute(e.file) + "\"/>\n";
  }
  out += "</Collection>\n</VTKFile>\n";
  return out;
}

}  // namespace clothsim
