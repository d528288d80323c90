// The colour comparison against known answers: a mesh equal to its reference, a mesh whose
// colour steps are halved, noise that must not pass for contrast, and vertices too far away.
#include <gtest/gtest.h>

#include <random>

#include "rangefuse/eval/ColourError.h"

using namespace rangefuse;

namespace {

constexpr int kSide = 40;  // vertices along each side of the grid

/// A flat grid on [0, 1]^2 at height z: orange left of x = 0.5, blue right of it.
TriangleMesh checkedGrid(double z) {
  TriangleMesh m;
  for (int j = 0; j < kSide; ++j)
    for (int i = 0; i < kSide; ++i) {
      const double x = double(i) / (kSide - 1), y = double(j) / (kSide - 1);
      m.vertices.emplace_back(x, y, z);
      m.colours.push_back(x < 0.5 ? Eigen::Vector3f(0.85f, 0.35f, 0.15f)
                                  : Eigen::Vector3f(0.15f, 0.45f, 0.80f));
    }
  for (int j = 0; j + 1 < kSide; ++j)
    for (int i = 0; i + 1 < kSide; ++i) {
      const int a = j * kSide + i;
      m.faces.push_back({a, a + 1, a + kSide + 1});
      m.faces.push_back({a, a + kSide + 1, a + kSide});
    }
  return m;
}

}  // namespace

TEST(ColourError, AMeshEqualToItsReferenceHasNoErrorAndFullContrast) {
  const TriangleMesh m = checkedGrid(0);
  const ColourComparison c = compareColours(m, m, 0.01, 0.06);
  EXPECT_EQ(c.vertices, m.vertices.size());
  EXPECT_NEAR(c.error.max, 0, 1e-4);
  // One column of edges crosses the step on each row: horizontal and diagonal edges.
  EXPECT_EQ(c.edges, size_t(2 * kSide - 1));
  EXPECT_NEAR(c.edgeContrast, 1, 1e-6);
}

TEST(ColourError, HalvedStepsGiveHalfTheContrastAndTheirError) {
  const TriangleMesh ref = checkedGrid(0);
  TriangleMesh m = ref;
  double want = 0;
  for (auto& colour : m.colours) {
    const Eigen::Vector3f before = colour;
    colour = 0.5f * colour + Eigen::Vector3f::Constant(0.25f);
    want += 255.0 * (colour - before).cwiseAbs().cast<double>().mean() / m.colours.size();
  }
  const ColourComparison c = compareColours(m, ref, 0.01, 0.06);
  EXPECT_NEAR(c.edgeContrast, 0.5, 1e-6);
  EXPECT_NEAR(c.error.mean, want, 1e-3);
}

TEST(ColourError, NoiseDoesNotPassForContrast) {
  const TriangleMesh ref = checkedGrid(0);
  TriangleMesh m = ref;
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0, 0.05f);
  for (auto& colour : m.colours)
    for (int k = 0; k < 3; ++k) colour[k] += noise(rng);
  const ColourComparison c = compareColours(m, ref, 0.01, 0.06);
  EXPECT_NEAR(c.edgeContrast, 1, 0.1);
  // The mean of |N(0, s)| is s sqrt(2 / pi).
  EXPECT_NEAR(c.error.mean, 255 * 0.05 * std::sqrt(2 / M_PI), 0.5);
}

TEST(ColourError, VerticesBeyondTheLimitAreNotCompared) {
  const TriangleMesh ref = checkedGrid(0);
  TriangleMesh m = checkedGrid(0.02);
  for (size_t i = 0; i < m.vertices.size() / 2; ++i) m.vertices[i].z() = 0.005;
  const ColourComparison c = compareColours(m, ref, 0.01, 0.06);
  EXPECT_EQ(c.vertices, m.vertices.size() / 2);
  EXPECT_NEAR(c.error.max, 0, 1e-4);
}

TEST(ColourError, ErrorNearTextureEdgesIsReportedApart) {
  // The step runs at x = 0.5, between columns 19 and 20 (spacing 1/39): within 0.06 of it lie
  // columns 18 to 21 of every row. Only those are greyed, so the far error is zero.
  const TriangleMesh ref = checkedGrid(0);
  TriangleMesh m = ref;
  const Eigen::Vector3f grey = Eigen::Vector3f::Constant(0.5f);
  double want = 0;
  for (int j = 0; j < kSide; ++j)
    for (int i = 18; i <= 21; ++i) {
      auto& colour = m.colours[size_t(j * kSide + i)];
      want += 255.0 * (grey - colour).cwiseAbs().cast<double>().mean();
      colour = grey;
    }
  const ColourComparison c = compareColours(m, ref, 0.01, 0.06);
  EXPECT_EQ(c.nearEdgeVertices, size_t(4 * kSide));
  EXPECT_EQ(c.farEdgeVertices, m.vertices.size() - 4 * kSide);
  EXPECT_NEAR(c.nearEdgeError.mean, want / (4 * kSide), 1e-3);
  EXPECT_NEAR(c.farEdgeError.max, 0, 1e-4);
}
