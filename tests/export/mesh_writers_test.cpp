#include "export/mesh_writers.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <sstream>

namespace clothsim {
namespace {

// Two triangles over four points, with a vector and a scalar field.
MeshPart square() {
  MeshPart part;
  part.name = "cloth";
  part.points = {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 1.f, 1.f, 0.1f, 0.f, 1.f, 1.0f / 3.0f};
  part.triangles = {0, 1, 2, 0, 2, 3};
  part.fields.push_back({"velocity", 3, {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12}});
  part.fields.push_back({"strain", 1, {0.5f, 0.25f, 0.125f, 1e-7f}});
  return part;
}

template <typename T>
T read_at(const std::string& bytes, std::size_t offset) {
  T value;
  std::memcpy(&value, bytes.data() + offset, sizeof(T));
  return value;
}

TEST(MeshWriters, APc2HeaderIsBlendersThirtyTwoBytes) {
  const std::string h = pc2_header(625, 0.0f, 1.0f, 151);
  ASSERT_EQ(h.size(), 32u);
  EXPECT_EQ(std::memcmp(h.data(), "POINTCACHE2\0", 12), 0);
  EXPECT_EQ(read_at<std::int32_t>(h, 12), 1);    // version
  EXPECT_EQ(read_at<std::int32_t>(h, 16), 625);  // points
  EXPECT_EQ(read_at<float>(h, 20), 0.0f);        // start frame
  EXPECT_EQ(read_at<float>(h, 24), 1.0f);        // sample rate: one frame
  EXPECT_EQ(read_at<std::int32_t>(h, 28), 151);  // samples
}

TEST(MeshWriters, APc2SampleIsEveryPointAsThreeFloatsInOrder) {
  const MeshPart part = square();
  const std::string s = pc2_sample(part);
  ASSERT_EQ(s.size(), 4 * part.points.size());
  for (std::size_t i = 0; i < part.points.size(); ++i) EXPECT_EQ(read_at<float>(s, 4 * i), part.points[i]);
}

TEST(MeshWriters, AnObjReadsBackToTheSameFloatsAndOneBasedFaces) {
  const MeshPart part = square();
  std::istringstream in(obj_text(part, "clothsim test"));
  std::vector<float> points;
  std::vector<std::uint32_t> faces;
  std::string word, object;
  while (in >> word) {
    if (word == "o") in >> object;
    if (word == "v")
      for (int k = 0; k < 3; ++k) {
        double value;
        in >> value;
        points.push_back(static_cast<float>(value));
      }
    if (word == "f")
      for (int k = 0; k < 3; ++k) {
        std::uint32_t i;
        in >> i;
        faces.push_back(i - 1);
      }
    if (word == "#") std::getline(in, word);
  }
  EXPECT_EQ(object, "cloth");
  EXPECT_EQ(points, part.points);  // %.9g: a float's round trip is exact
  EXPECT_EQ(faces, part.triangles);
}

TEST(MeshWriters, APlyHeaderNamesEveryFieldAndItsBodyHoldsThemAsLittleEndianFloats) {
  const MeshPart part = square();
  const std::string bytes = ply_bytes(part, "clothsim test");
  const std::string header_end = "end_header\n";
  const std::size_t body = bytes.find(header_end) + header_end.size();
  const std::string header = bytes.substr(0, body);
  EXPECT_NE(header.find("format binary_little_endian 1.0\n"), std::string::npos);
  EXPECT_NE(header.find("element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                        "property float vx\nproperty float vy\nproperty float vz\nproperty float strain\n"
                        "element face 2\nproperty list uchar int vertex_indices\n"),
            std::string::npos);
  const std::size_t vertex_bytes = 7 * 4, face_bytes = 1 + 3 * 4;
  ASSERT_EQ(bytes.size(), body + 4 * vertex_bytes + 2 * face_bytes);
  EXPECT_EQ(read_at<float>(bytes, body + 2 * vertex_bytes + 2 * 4), 0.1f);  // z of point 2
  EXPECT_EQ(read_at<float>(bytes, body + 3 * vertex_bytes + 3 * 4), 10.f);  // vx of point 3
  EXPECT_EQ(read_at<float>(bytes, body + 3 * vertex_bytes + 6 * 4), 1e-7f);  // strain of point 3
  const std::size_t faces = body + 4 * vertex_bytes;
  EXPECT_EQ(static_cast<int>(bytes[faces]), 3);
  EXPECT_EQ(read_at<std::int32_t>(bytes, faces + face_bytes + 1 + 2 * 4), 3);  // last index of face 1
}

TEST(MeshWriters, AVtpPieceCountsPointsAndPolysAndNamesEveryField) {
  const std::string text = vtp_text(square());
  EXPECT_NE(text.find("<Piece NumberOfPoints=\"4\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" "
                      "NumberOfPolys=\"2\">"),
            std::string::npos);
  EXPECT_NE(text.find("Name=\"velocity\" NumberOfComponents=\"3\""), std::string::npos);
  EXPECT_NE(text.find("Name=\"strain\" NumberOfComponents=\"1\""), std::string::npos);
  EXPECT_NE(text.find("Name=\"connectivity\" format=\"ascii\">\n0 1 2 0 2 3 \n"), std::string::npos);
  EXPECT_NE(text.find("Name=\"offsets\" format=\"ascii\">\n3 6 \n"), std::string::npos);
}

TEST(MeshWriters, EachPvdDataSetCarriesItsTimePartAndFile) {
  const std::string text = pvd_text({{0.0, 0, "run/cloth_00000.vtp"}, {1.0 / 30, 1, "run/sphere0_00001.vtp"}});
  EXPECT_NE(text.find("<DataSet timestep=\"0\" group=\"\" part=\"0\" file=\"run/cloth_00000.vtp\"/>"), std::string::npos);
  EXPECT_NE(text.find("<DataSet timestep=\"0.033333333333333333\" group=\"\" part=\"1\" file=\"run/sphere0_00001.vtp\"/>"),
            std::string::npos);
}

}  // namespace
}  // namespace clothsim
