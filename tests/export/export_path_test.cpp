#include "export/export_path.h"

#include <gtest/gtest.h>

namespace clothsim {
namespace {

TEST(ExportPath, ASequenceNamesEachFrameAndSphereByItsNumber) {
  const ExportPath p = parse_export_path("out/frame_%05d.obj");
  EXPECT_EQ(p.format, ExportFormat::Obj);
  EXPECT_EQ(p.dir, "out");
  EXPECT_EQ(p.frame_file(12), "out/frame_00012.obj");
  EXPECT_EQ(p.frame_file(3, 1), "out/frame_sphere1_00003.obj");
  EXPECT_TRUE(p.final_files(2).empty());  // every file is named as it is written
}

TEST(ExportPath, ASequenceWithoutADirectoryIsWrittenHere) {
  const ExportPath p = parse_export_path("c%3d.PLY");
  EXPECT_EQ(p.format, ExportFormat::Ply);
  EXPECT_EQ(p.frame_file(7), "./c007.PLY");
}

TEST(ExportPath, APointCacheComesWithItsRestMeshAndOnePairPerSphere) {
  const ExportPath p = parse_export_path("dir/cloth.pc2");
  EXPECT_EQ(p.format, ExportFormat::Pc2);
  EXPECT_EQ(p.final_files(1),
            (std::vector<std::string>{"dir/cloth.pc2", "dir/cloth.obj", "dir/cloth.sphere0.pc2", "dir/cloth.sphere0.obj"}));
}

TEST(ExportPath, ACollectionIndexesVtpFilesInADirectoryOfItsName) {
  const ExportPath p = parse_export_path("r/run.pvd");
  EXPECT_EQ(p.dir, "r/run");
  EXPECT_EQ(p.frame_file(2), "r/run/cloth_00002.vtp");
  EXPECT_EQ(p.frame_file(2, 0), "r/run/sphere0_00002.vtp");
  EXPECT_EQ(p.final_files(3), std::vector<std::string>{"r/run.pvd"});
}

TEST(ExportPath, BadPathsAreRefusedWithTheFormsThatWork) {
  for (const char* bad : {"out.stl", "out/frame.obj", "out/f_%05d_%d.obj", "out/f_%s.ply", "out/f_%05d.obj.gz",
                          "a_%05d.pc2", ".pvd", "out/%05x.obj"}) {
    try {
      parse_export_path(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const ExportError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(std::string("--export: ") + bad + ": ", 0), 0u) << e.what();
    }
  }
}

}  // namespace
}  // namespace clothsim
