// The file formats of mesh export, as bytes: each function returns a whole file (or, for PC2,
// a header and a sample), so writing it is one atomic output (io/output_file.h) and a
// test reads the layout back without a disk.
//   OBJ   Wavefront text: "o NAME", v lines (%.9g: a float32 read back is the same float), 1-based f
//   PLY   binary little-endian 1.0: float x y z, every field as float properties (velocity as
//         vx vy vz), faces as uchar-counted int lists
//   VTP   VTK XML PolyData 0.1, ASCII: Points (Float32), Polys, PointData with every field
//   PC2   Point Cache 2 (Blender's MOD_meshcache_pc2.cc): 32-byte header "POINTCACHE2\0", int32
//         version 1, int32 points, float start frame, float sample rate (frames), int32 samples,
//         then per sample the points as float32 x y z, little-endian
//   PVD   ParaView's collection: one DataSet per file with timestep, part and relative file
#pragma once

#include <string>
#include <vector>

#include "export/mesh_part.h"

namespace clothsim {

std::string obj_text(const MeshPart& part, const std::string& comment);
std::string ply_bytes(const MeshPart& part, const std::string& comment);
std::string vtp_text(const MeshPart& part);

inline constexpr int kPc2HeaderBytes = 32;
std::string pc2_header(int points, float start_frame, float sample_rate, int samples);
std::string pc2_sample(const MeshPart& part);  // its points, float32 little-endian

struct PvdEntry {
  double t = 0.0;    // s
  int part = 0;      // 0 the cloth, 1 + s sphere s
  std::string file;  // relative to the .pvd
};
std::string pvd_text(const std::vector<PvdEntry>& entries);

}  // namespace clothsim
