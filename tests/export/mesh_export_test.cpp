#include "export/mesh_export.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "export/mesh_part.h"
#include "test_support.h"

namespace clothsim {
namespace {
namespace fs = std::filesystem;

// A 3 x 2 cloth and one dynamic sphere.
const char* const kScene = R"(
name: tiny
duration: 0.1
dt: 1.0e-3
integrator: rk4
gravity: [0, -9.8, 0]
cloth:
  particles: [3, 2]
  size: [1, 1]
  center: [0, 1, 0]
  plane: xz
  particle_mass: 0.1
  springs:
    structural: {stiffness: 100, damping: 1}
spheres:
  - {center: [0, 0, 0], radius: 0.5, kinematic: false, mass: 2.0}
)";

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::path(CLOTHSIM_TEST_OUTPUT_DIR) / "export" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Frames 0, 1, 2 of `model` moved by hand: frame k's positions shifted by k m along x.
void export_three(MeshExport& out, const Model& model) {
  State s = initial_state(model);
  for (int k = 0; k < 3; ++k) {
    State frame = s;
    frame.x.row(0).array() += k;
    frame.t = k / 30.0;
    std::vector<float> error(static_cast<std::size_t>(model.num_particles), 1e-3f * static_cast<float>(k));
    out.add(k, frame, &error);
  }
}

std::size_t hidden_files(const fs::path& dir) {
  std::size_t n = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir)) n += e.path().filename().string()[0] == '.';
  return n;
}

TEST(MeshExport, APointCacheHoldsEveryFrameAndItsRestMeshTheFirst) {
  const Model model = testing::model_from_yaml(kScene);
  const fs::path dir = fresh_dir("pc2");
  MeshExport out(model, parse_export_path((dir / "c.pc2").string()), 30.0, false);
  export_three(out, model);
  EXPECT_FALSE(fs::exists(dir / "c.pc2"));  // named only when complete
  out.finish();
  const std::string pc2 = slurp(dir / "c.pc2");
  ASSERT_EQ(pc2.size(), 32u + 3 * 6 * 12);
  std::int32_t points, samples;
  std::memcpy(&points, pc2.data() + 16, 4);
  std::memcpy(&samples, pc2.data() + 28, 4);
  EXPECT_EQ(points, 6);
  EXPECT_EQ(samples, 3);
  float x_last;  // particle 5's x in frame 2: its rest x + 2
  std::memcpy(&x_last, pc2.data() + 32 + (2 * 6 + 5) * 12, 4);
  EXPECT_EQ(x_last, static_cast<float>(initial_state(model).x(0, 5) + 2));
  const std::string rest = slurp(dir / "c.obj");
  EXPECT_EQ(std::count(rest.begin(), rest.end(), '\n'), 1 + 1 + 6 + 4);  // comment, o, v, f
  // The sphere: its own cache over its own mesh.
  const std::size_t sphere_points = 2 + (kSphereRings - 1) * kSphereSegments;
  EXPECT_EQ(slurp(dir / "c.sphere0.pc2").size(), 32 + 3 * sphere_points * 12);
  EXPECT_TRUE(fs::exists(dir / "c.sphere0.obj"));
  EXPECT_EQ(out.written(), (dir / "c.pc2").string() + ", " + (dir / "c.obj").string() + ", " +
                               (dir / "c.sphere0.pc2").string() + ", " + (dir / "c.sphere0.obj").string());
  EXPECT_EQ(hidden_files(dir), 0u);
}

TEST(MeshExport, APointCacheNotFinishedLeavesNothing) {
  const Model model = testing::model_from_yaml(kScene);
  const fs::path dir = fresh_dir("pc2_dropped");
  {
    MeshExport out(model, parse_export_path((dir / "c.pc2").string()), 30.0, false);
    export_three(out, model);
  }
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(MeshExport, ASequenceWritesAFilePerFrameAndSphereWithTheErrorWhenAsked) {
  const Model model = testing::model_from_yaml(kScene);
  const fs::path dir = fresh_dir("ply");
  MeshExport out(model, parse_export_path((dir / "f_%03d.ply").string()), 30.0, true);
  export_three(out, model);
  out.finish();
  for (const char* name : {"f_000.ply", "f_001.ply", "f_002.ply", "f_sphere0_000.ply", "f_sphere0_002.ply"})
    EXPECT_TRUE(fs::exists(dir / name)) << name;
  EXPECT_NE(slurp(dir / "f_001.ply").find("property float speed\nproperty float strain\nproperty float error\n"),
            std::string::npos);
  EXPECT_EQ(out.written(), "6 PLY files in " + dir.string() + "/");
}

TEST(MeshExport, ACollectionIndexesEveryFrameOfEveryPartAtItsTime) {
  const Model model = testing::model_from_yaml(kScene);
  const fs::path dir = fresh_dir("pvd");
  MeshExport out(model, parse_export_path((dir / "r.pvd").string()), 30.0, false);
  export_three(out, model);
  EXPECT_FALSE(fs::exists(dir / "r.pvd"));
  EXPECT_TRUE(fs::exists(dir / "r" / "cloth_00002.vtp"));  // each frame's file named as written
  out.finish();
  const std::string pvd = slurp(dir / "r.pvd");
  EXPECT_EQ(std::count(pvd.begin(), pvd.end(), '\n'), 5 + 6);  // 3 frames x (cloth, sphere)
  EXPECT_NE(pvd.find("timestep=\"0.066666666666666666\" group=\"\" part=\"1\" file=\"r/sphere0_00002.vtp\""),
            std::string::npos);
  EXPECT_EQ(slurp(dir / "r" / "cloth_00000.vtp").find("Name=\"error\""), std::string::npos);  // not asked for
}

TEST(MeshExport, TheClothsFieldsAreItsVelocitySpeedAndStrain) {
  const Model model = testing::model_from_yaml(kScene);
  State s = initial_state(model);
  s.v.col(4) << 3.0, 0.0, 4.0;
  s.x(0, 0) += 0.25;  // particle 0 halfway to particle 1: their spring (0.5 m) at half length
  const MeshPart part = cloth_part(model, s, nullptr);
  ASSERT_EQ(part.fields.size(), 3u);
  EXPECT_EQ(part.fields[0].values[3 * 4 + 2], 4.0f);
  EXPECT_EQ(part.fields[1].values[4], 5.0f);
  EXPECT_GT(part.fields[2].values[1], 0.0f);
  EXPECT_EQ(part.triangles, model.triangles);
}

}  // namespace
}  // namespace clothsim

namespace clothsim {
namespace {

std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

TEST(MeshExport, AShorterRerunRemovesTheLongerRunsLaterFramesOfItsSeriesOnly) {
  // A 10-frame run over a 31-frame one left 31 files a series (--frames removes them).
  const Model model = testing::model_from_yaml(kScene);
  for (const char* pattern : {"f_%03d.obj", "f_%03d.ply", "r.pvd"}) {
    const fs::path dir = fresh_dir("rerun");
    const ExportPath path = parse_export_path((dir / pattern).string());
    {
      MeshExport longer(model, path, 30.0, false);
      State s = initial_state(model);
      for (int k = 0; k < 5; ++k) longer.add(k, s);
      longer.finish();
    }
    const fs::path series = path.format == ExportFormat::Pvd ? dir / "r" : dir;
    // Not of the series: another name, %03d never writes "0004", another prefix.
    for (const char* other : {"f_notes.txt", "f_0004.obj", "g_004.obj"}) std::ofstream(series / other) << "keep";
    MeshExport shorter(model, path, 30.0, false);
    export_three(shorter, model);
    shorter.finish();
    std::vector<std::string> expected;
    if (path.format == ExportFormat::Pvd)
      expected = {"cloth_00000.vtp", "cloth_00001.vtp", "cloth_00002.vtp", "f_0004.obj", "f_notes.txt", "g_004.obj",
                  "sphere0_00000.vtp", "sphere0_00001.vtp", "sphere0_00002.vtp"};
    else {
      const std::string ext = path.suffix;
      expected = {"f_000" + ext, "f_001" + ext, "f_002" + ext, "f_0004.obj", "f_notes.txt", "f_sphere0_000" + ext,
                  "f_sphere0_001" + ext, "f_sphere0_002" + ext, "g_004.obj"};
      std::sort(expected.begin(), expected.end());
    }
    EXPECT_EQ(names_in(series), expected) << pattern;
  }
}

TEST(MeshExport, FilesGoneMidRunAreNeverIndexedNorCountedAsKept) {
  // The PVD folder removed mid-run: exit 0 with an index over missing files; an OBJ folder moved
  // away: "kept 464 OBJ files in ex/".
  const Model model = testing::model_from_yaml(kScene);
  for (const char* pattern : {"r.pvd", "ex/f_%03d.obj"}) {
    const fs::path dir = fresh_dir("gone");
    const ExportPath path = parse_export_path((dir / pattern).string());
    MeshExport out(model, path, 30.0, false);
    export_three(out, model);
    EXPECT_EQ(out.unwritten(), path.final_files(1));
    fs::rename(path.dir, dir / "moved");
    EXPECT_EQ(out.written(), "") << "nothing of it is where it was written";
    EXPECT_EQ(out.lost(), "6 " + std::string(path.format == ExportFormat::Pvd ? "VTP" : "OBJ") + " files gone from " +
                              path.dir + "/ (moved or removed during the run)");
    try {
      out.finish();
      ADD_FAILURE() << pattern << ": finished over missing files";
    } catch (const ExportError& e) {
      EXPECT_NE(std::string(e.what()).find("cannot finish " + path.path + ": 6 of the 6"), std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find(path.dir + " was moved or removed during the run"), std::string::npos);
    }
    EXPECT_FALSE(fs::exists(dir / "r.pvd"));
    EXPECT_EQ(out.unwritten(), path.final_files(1)) << "still not written";
  }
}

TEST(MeshExport, WhatFinishWouldNameIsUnwrittenUntilItHas) {
  const Model model = testing::model_from_yaml(kScene);
  const fs::path dir = fresh_dir("unwritten");
  MeshExport out(model, parse_export_path((dir / "c.pc2").string()), 30.0, false);
  export_three(out, model);
  EXPECT_EQ(out.unwritten(), (std::vector<std::string>{(dir / "c.pc2").string(), (dir / "c.obj").string(),
                                                       (dir / "c.sphere0.pc2").string(),
                                                       (dir / "c.sphere0.obj").string()}));
  out.finish();
  EXPECT_TRUE(out.unwritten().empty());
}

}  // namespace clothsim
