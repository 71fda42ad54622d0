// The khz tool's renderer: camera, rasterizer and PNG files, checked by properties of the
// pictures (coverage, areas, occlusion, colours, positions) rather than by bytes.
#include <khz/reduced/errors.hpp>
#include <khz/render/camera.hpp>
#include <khz/render/image.hpp>
#include <khz/render/png_file.hpp>
#include <khz/render/rasterizer.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <map>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace khz::render {
namespace {

using reduced::TriangleMatrix;
using reduced::VertexMatrix;

constexpr Color white{255, 255, 255};
constexpr Color red{255, 0, 0};
constexpr Color blue{0, 0, 255};
constexpr Color grey{128, 128, 128};
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

/// An icosahedron subdivided `levels` times and pushed onto a sphere; triangles
/// counter-clockwise seen from outside.
struct Sphere {
  VertexMatrix vertices;
  TriangleMatrix triangles;
};

Sphere icosphere(int levels, double radius, const Eigen::Vector3d& centre) {
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> points = {{-1, phi, 0}, {1, phi, 0}, {-1, -phi, 0}, {1, -phi, 0},
                                         {0, -1, phi}, {0, 1, phi}, {0, -1, -phi}, {0, 1, -phi},
                                         {phi, 0, -1}, {phi, 0, 1}, {-phi, 0, -1}, {-phi, 0, 1}};
  std::vector<std::array<int, 3>> faces = {
      {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> midpoints;
    const auto midpoint = [&](int a, int b) {
      const std::pair<int, int> key = std::minmax(a, b);
      const auto [it, inserted] = midpoints.try_emplace(key, static_cast<int>(points.size()));
      if (inserted) points.push_back((points[a] + points[b]) / 2.0);
      return it->second;
    };
    std::vector<std::array<int, 3>> finer;
    for (const auto& [a, b, c] : faces) {
      const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      finer.insert(finer.end(), {{a, ab, ca}, {b, bc, ab}, {c, ca, bc}, {ab, bc, ca}});
    }
    faces = std::move(finer);
  }
  Sphere sphere;
  sphere.vertices.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i) {
    sphere.vertices.row(static_cast<Eigen::Index>(i)) =
        (centre + radius * points[i].normalized()).transpose();
  }
  sphere.triangles.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) sphere.triangles(static_cast<Eigen::Index>(f), k) = faces[f][k];
  }
  return sphere;
}

/// Looks down −z at the origin from (0, 0, distance).
Camera camera_on_z(double distance, int width = 160, int height = 120,
                   double vertical_fov = 40.0 * std::numbers::pi / 180.0) {
  return Camera({0.0, 0.0, distance}, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(),
                vertical_fov, width, height);
}

int count_pixels(const Image& image, Color color) {
  int count = 0;
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) count += image.pixel(x, y) == color;
  }
  return count;
}

/// The pixel containing a projected point.
Color pixel_at(const Image& image, const ScreenPoint& point) {
  return image.pixel(static_cast<int>(point.pixel.x()), static_cast<int>(point.pixel.y()));
}

VertexMatrix rows(std::initializer_list<Eigen::Vector3d> points) {
  VertexMatrix matrix(static_cast<Eigen::Index>(points.size()), 3);
  Eigen::Index i = 0;
  for (const Eigen::Vector3d& p : points) matrix.row(i++) = p.transpose();
  return matrix;
}

/// Runs `f` and returns the message of the `Exception` it throws ("" if it throws none).
template <class Exception, class F>
std::string thrown_message(F&& f) {
  try {
    f();
  } catch (const Exception& error) {
    return error.what();
  }
  return "";
}

// --- Image -------------------------------------------------------------------------------------

TEST(Image, StoresRowsTopDownAsRgbBytes) {
  Image image(3, 2, blue);
  image.set_pixel(2, 1, red);
  EXPECT_EQ(image.pixel(2, 1), red);
  EXPECT_EQ(image.pixel(1, 1), blue);
  ASSERT_EQ(image.bytes().size(), 18u);
  const std::size_t offset = 3 * (1 * 3 + 2);
  EXPECT_EQ(image.bytes()[offset], 255);
  EXPECT_EQ(image.bytes()[offset + 2], 0);
  EXPECT_EQ(image.bytes()[2], 255);  // blue channel of pixel (0, 0)
}

TEST(Image, RejectsSizesOutOfRange) {
  EXPECT_NE(thrown_message<reduced::Error>([] { Image(0, 10); }).find("width 0"),
            std::string::npos);
  EXPECT_NE(thrown_message<reduced::Error>([] { Image(10, Image::max_size + 1); }).find("height"),
            std::string::npos);
}

// --- Camera ------------------------------------------------------------------------------------

TEST(Camera, ProjectsTargetToCentreAndOrientsTheImage) {
  const Camera camera = camera_on_z(5.0, 200, 100);
  const auto centre = camera.project(Eigen::Vector3d::Zero());
  ASSERT_TRUE(centre.has_value());
  EXPECT_NEAR(centre->pixel.x(), 100.0, 1e-12);
  EXPECT_NEAR(centre->pixel.y(), 50.0, 1e-12);
  EXPECT_NEAR(centre->depth, 5.0, 1e-12);
  // World +x is image right, world +y is image up (smaller rows).
  EXPECT_GT(camera.project(Eigen::Vector3d::UnitX())->pixel.x(), 100.0);
  EXPECT_LT(camera.project(Eigen::Vector3d::UnitY())->pixel.y(), 50.0);
  // A point on the upper edge of the field of view lands on the top image row.
  const double top = 5.0 * std::tan(camera.vertical_fov() / 2.0);
  EXPECT_NEAR(camera.project({0.0, top, 0.0})->pixel.y(), 0.0, 1e-9);
  // Twice as far, half the offset from the centre.
  const double near_offset = camera.project({1.0, 0.0, 0.0})->pixel.x() - 100.0;
  const double far_offset = camera.project({1.0, 0.0, -5.0})->pixel.x() - 100.0;
  EXPECT_NEAR(far_offset, near_offset / 2.0, 1e-9);
}

TEST(Camera, RejectsPointsBehindTheEyeAndNonFinitePoints) {
  const Camera camera = camera_on_z(5.0);
  EXPECT_FALSE(camera.project({0.0, 0.0, 6.0}).has_value());
  EXPECT_FALSE(camera.project({0.0, 0.0, 5.0}).has_value());
  EXPECT_FALSE(camera.project({nan, 0.0, 0.0}).has_value());
  EXPECT_TRUE(camera.project({0.0, 0.0, 4.9}).has_value());
}

TEST(Camera, RejectsInvalidParameters) {
  const Eigen::Vector3d up = Eigen::Vector3d::UnitY();
  const Eigen::Vector3d eye(0, 0, 1);
  EXPECT_NE(
      thrown_message<reduced::Error>([&] { Camera(eye, eye, up, 1.0, 10, 10); }).find("coincide"),
      std::string::npos);
  EXPECT_NE(thrown_message<reduced::Error>([&] {
              Camera(eye, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 1.0, 10, 10);
            }).find("parallel"),
            std::string::npos);
  EXPECT_NE(thrown_message<reduced::Error>([&] {
              Camera(eye, Eigen::Vector3d::Zero(), up, 0.0, 10, 10);
            }).find("vertical_fov"),
            std::string::npos);
  EXPECT_NE(thrown_message<reduced::Error>([&] {
              Camera(eye, Eigen::Vector3d::Zero(), up, std::numbers::pi, 10, 10);
            }).find("vertical_fov"),
            std::string::npos);
  EXPECT_NE(thrown_message<reduced::Error>([&] {
              Camera(eye, Eigen::Vector3d::Zero(), up, 1.0, 0, 10);
            }).find("width"),
            std::string::npos);
  EXPECT_NE(thrown_message<reduced::Error>([&] {
              Camera({nan, 0, 0}, Eigen::Vector3d::Zero(), up, 1.0, 10, 10);
            }).find("eye"),
            std::string::npos);
}

TEST(Camera, FrameBoxFitsEveryCornerTightly) {
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-1.0, 0.0, -0.5), Eigen::Vector3d(2.0, 1.0, 0.5));
  const double margin = 0.1;
  // The last direction is parallel to `up`, which frame_box must replace.
  for (const Eigen::Vector3d& direction :
       {Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(1, -0.5, -2), Eigen::Vector3d(-3, 1, 0.2),
        Eigen::Vector3d(0, -1, 0)}) {
    const Camera camera =
        frame_box(box, direction, Eigen::Vector3d::UnitY(), 0.8, 320, 200, margin);
    EXPECT_TRUE(camera.forward().isApprox(direction.normalized(), 1e-12));
    double largest = 0.0;  // largest corner offset from the centre, in half-sizes
    for (int i = 0; i < 8; ++i) {
      const auto corner =
          camera.project(box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(i)));
      ASSERT_TRUE(corner.has_value());
      largest = std::max({largest, std::abs(corner->pixel.x() - 160.0) / 160.0,
                          std::abs(corner->pixel.y() - 100.0) / 100.0});
    }
    EXPECT_NEAR(largest, 1.0 - margin, 1e-9) << direction.transpose();
  }
  const Eigen::AlignedBox3d point(Eigen::Vector3d::Ones(), Eigen::Vector3d::Ones());
  EXPECT_NEAR((frame_box(point, {0, 0, -1}, Eigen::Vector3d::UnitY(), 0.8, 10, 10).eye() -
               Eigen::Vector3d(1, 1, 2))
                  .norm(),
              0.0, 1e-12);
  EXPECT_THROW(frame_box(Eigen::AlignedBox3d(), {0, 0, -1}, Eigen::Vector3d::UnitY(), 0.8, 10, 10),
               reduced::Error);
  EXPECT_THROW(frame_box(box, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(), 0.8, 10, 10),
               reduced::Error);
  EXPECT_THROW(frame_box(box, {0, 0, -1}, Eigen::Vector3d::UnitY(), 0.8, 10, 10, 1.0),
               reduced::Error);
}

// --- Meshes ------------------------------------------------------------------------------------

TEST(Rasterizer, SphereCoversTheCentreAndLeavesTheCornersBackground) {
  const Sphere sphere = icosphere(3, 1.0, Eigen::Vector3d::Zero());
  Rasterizer rasterizer(camera_on_z(5.0), white);
  rasterizer.draw_mesh(sphere.vertices, sphere.triangles, {.color = blue, .ambient = 1.0});
  const Image& image = rasterizer.image();
  EXPECT_EQ(image.pixel(80, 60), blue);
  for (const auto& [x, y] : {std::pair{0, 0}, {159, 0}, {0, 119}, {159, 119}}) {
    EXPECT_EQ(image.pixel(x, y), white) << x << ", " << y;
    EXPECT_EQ(rasterizer.depth(x, y), std::numeric_limits<double>::infinity());
  }
  // The nearest point of the sphere is 4 units from the eye.
  EXPECT_NEAR(rasterizer.depth(80, 60), 4.0, 0.01);
}

TEST(Rasterizer, SphereSilhouetteHasTheProjectedDiscArea) {
  // A sphere of radius R seen from distance D subtends a cone of half-angle asin(R / D), which
  // meets the image plane in a disc of radius f tan(asin(R / D)) pixels around the centre.
  const double radius = 1.0;
  const double distance = 4.0;
  const Camera camera = camera_on_z(distance, 400, 400);
  const Sphere sphere = icosphere(4, radius, Eigen::Vector3d::Zero());
  Rasterizer rasterizer(camera, white);
  rasterizer.draw_mesh(sphere.vertices, sphere.triangles, {.color = blue, .ambient = 1.0});

  const double disc_radius = camera.focal_length() * std::tan(std::asin(radius / distance));
  const double expected = std::numbers::pi * disc_radius * disc_radius;
  const int area = count_pixels(rasterizer.image(), blue);
  EXPECT_NEAR(area / expected, 1.0, 0.02) << area << " pixels, expected " << expected;
  // And it is centred.
  double sum_x = 0.0, sum_y = 0.0;
  for (int y = 0; y < 400; ++y) {
    for (int x = 0; x < 400; ++x) {
      if (rasterizer.image().pixel(x, y) != blue) continue;
      sum_x += x + 0.5;
      sum_y += y + 0.5;
    }
  }
  EXPECT_NEAR(sum_x / area, 200.0, 0.5);
  EXPECT_NEAR(sum_y / area, 200.0, 0.5);
}

TEST(Rasterizer, NearerGeometryOccludesFartherInEitherDrawingOrder) {
  const Sphere near_sphere = icosphere(3, 0.3, {0.0, 0.0, 1.5});
  const Sphere far_sphere = icosphere(3, 1.0, Eigen::Vector3d::Zero());
  for (const bool near_first : {true, false}) {
    Rasterizer rasterizer(camera_on_z(4.0), white);
    const auto draw_near = [&] {
      rasterizer.draw_mesh(near_sphere.vertices, near_sphere.triangles,
                           {.color = red, .ambient = 1.0});
    };
    const auto draw_far = [&] {
      rasterizer.draw_mesh(far_sphere.vertices, far_sphere.triangles,
                           {.color = blue, .ambient = 1.0});
    };
    if (near_first) {
      draw_near();
      draw_far();
    } else {
      draw_far();
      draw_near();
    }
    const Image& image = rasterizer.image();
    EXPECT_EQ(image.pixel(80, 60), red) << near_first;
    EXPECT_NEAR(rasterizer.depth(80, 60), 4.0 - 1.8, 0.01);
    // Beside the small sphere, the large one shows.
    EXPECT_EQ(image.pixel(80, 25), blue) << near_first;
  }
}

TEST(Rasterizer, LambertShadingIsBrightestFacingTheHeadlight) {
  const Sphere sphere = icosphere(4, 1.0, Eigen::Vector3d::Zero());
  TriangleMatrix inside_out = sphere.triangles;
  inside_out.col(1).swap(inside_out.col(2));
  const Camera camera = camera_on_z(4.0, 200, 200);
  const double silhouette = camera.focal_length() * std::tan(std::asin(1.0 / 4.0));
  const int rim_x = 100 + static_cast<int>(0.97 * silhouette);
  const Color base{200, 180, 160};
  for (const bool smooth : {false, true}) {
    for (const TriangleMatrix* triangles :
         std::array<const TriangleMatrix*, 2>{&sphere.triangles, &inside_out}) {
      Rasterizer rasterizer(camera, white);
      rasterizer.draw_mesh(sphere.vertices, *triangles,
                           {.color = base, .ambient = 0.2, .smooth = smooth});
      const Color centre = rasterizer.image().pixel(100, 100);
      const Color rim = rasterizer.image().pixel(rim_x, 100);
      // Facing the eye: the full colour (to within the facets' tilt).
      EXPECT_NEAR(centre.r, 200, 2) << smooth;
      EXPECT_NEAR(centre.b, 160, 2) << smooth;
      // Near the silhouette the surface is seen at a grazing angle: much darker, but never
      // below the ambient level.
      EXPECT_LT(rim.r, 0.6 * centre.r) << smooth;
      EXPECT_GE(rim.r, 0.2 * 200 - 1) << smooth;
      EXPECT_NE(rim, white) << smooth;
    }
  }
}

TEST(Rasterizer, AdjacentTrianglesLeaveNoGaps) {
  // A jittered grid of triangles covering more than the field of view: with any gap, a
  // background pixel would show through. The grid lines x = 0 and y = 0 stay straight and, in
  // an image of odd size, project exactly onto a column and a row of pixel centres: those
  // pixels lie on edges shared by two triangles and must be drawn by at least one of them.
  const int n = 40;
  VertexMatrix vertices((n + 1) * (n + 1), 3);
  std::uint32_t state = 12345;
  const auto jitter = [&state] {
    state = state * 1664525u + 1013904223u;
    return (static_cast<double>(state >> 8) / (1 << 24) - 0.5) * 0.04;
  };
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const bool fixed = i == 0 || j == 0 || i == n || j == n || i == n / 2 || j == n / 2;
      vertices.row(j * (n + 1) + i) << -2.0 + 4.0 * i / n + (fixed ? 0.0 : jitter()),
          -2.0 + 4.0 * j / n + (fixed ? 0.0 : jitter()), fixed ? 0.0 : jitter();
    }
  }
  TriangleMatrix triangles(2 * n * n, 3);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      const int t = 2 * (j * n + i);
      if ((i + j) % 2 == 0) {
        triangles.row(t) << a, b, d;
        triangles.row(t + 1) << a, d, c;
      } else {
        triangles.row(t) << a, b, c;
        triangles.row(t + 1) << b, d, c;
      }
    }
  }
  for (const double distance : {3.0, 2.5}) {
    Rasterizer rasterizer(camera_on_z(distance, 201, 201, 1.0), white);
    rasterizer.draw_mesh(vertices, triangles, {.color = grey, .ambient = 1.0});
    EXPECT_EQ(count_pixels(rasterizer.image(), grey), 201 * 201) << distance;
  }
}

TEST(Rasterizer, ClipsTrianglesThatReachBehindTheEye) {
  // A floor under the eye, reaching far in front of and behind it: only the part in front
  // shows, filling the image below the horizon.
  const VertexMatrix floor =
      rows({{-100, -1, -100}, {100, -1, -100}, {100, -1, 100}, {-100, -1, 100}});
  TriangleMatrix triangles(2, 3);
  triangles << 0, 1, 2, 0, 2, 3;
  const Camera camera({0, 0, 0}, {0, 0, -1}, Eigen::Vector3d::UnitY(), 1.0, 160, 120);
  Rasterizer rasterizer(camera, white);
  rasterizer.draw_mesh(floor, triangles, {.color = grey, .ambient = 1.0});
  const Image& image = rasterizer.image();
  for (int x = 0; x < 160; ++x) {
    EXPECT_EQ(image.pixel(x, 119), grey) << x;
    EXPECT_EQ(image.pixel(x, 70), grey) << x;
    EXPECT_EQ(image.pixel(x, 0), white) << x;
    EXPECT_EQ(image.pixel(x, 55), white) << x;
  }
  // The bottom row's pixel centres look 59.5 pixels below the axis and meet the floor, 1 below
  // the eye, at depth f / 59.5.
  EXPECT_NEAR(rasterizer.depth(80, 119), camera.focal_length() / 59.5, 1e-4);

  // Entirely behind the eye: nothing.
  Rasterizer behind(camera, white);
  const VertexMatrix back = rows({{-1, -1, 1}, {1, -1, 1}, {0, 1, 2}});
  behind.draw_mesh(back, TriangleMatrix{{0, 1, 2}});
  EXPECT_EQ(count_pixels(behind.image(), white), 160 * 120);
}

TEST(Rasterizer, SkipsDegenerateAndNonFiniteGeometryWithoutCrashing) {
  Rasterizer rasterizer(camera_on_z(5.0), white);
  rasterizer.draw_mesh(VertexMatrix(0, 3), TriangleMatrix(0, 3));
  const VertexMatrix vertices = rows({{0, 0, 0},
                                      {1, 0, 0},
                                      {2, 0, 0},
                                      {nan, 0, 0},
                                      {0, std::numeric_limits<double>::infinity(), 0},
                                      {0, 1, 0}});
  // Repeated index, collinear, NaN corner, infinite corner.
  const TriangleMatrix degenerate{{0, 0, 1}, {0, 1, 2}, {0, 1, 3}, {0, 4, 1}, {3, 3, 3}};
  rasterizer.draw_mesh(vertices, degenerate, {.color = grey, .smooth = true});
  rasterizer.draw_mesh(vertices, degenerate, {.color = grey});
  EXPECT_EQ(count_pixels(rasterizer.image(), white), 160 * 120);
  // A valid triangle next to broken ones still draws (the NaN vertex is not used by it).
  rasterizer.draw_mesh(vertices, TriangleMatrix{{0, 1, 3}, {0, 1, 5}},
                       {.color = grey, .ambient = 1.0});
  EXPECT_GT(count_pixels(rasterizer.image(), grey), 100);

  Rasterizer points(camera_on_z(5.0), white);
  const std::vector<Color> one{red};
  points.draw_points(VertexMatrix(0, 3), {});
  points.draw_points(rows({{nan, 0, 0}, {0, 0, 6}, {0, 0, 5}}), one);
  points.draw_arrow({nan, 0, 0}, {1, 0, 0});
  points.draw_arrow({1, 0, 0}, {1, 0, 0});
  points.draw_arrow({0, 0, 6}, {0, 0, 7});   // behind the eye
  points.draw_arrow({0, 0, 0}, {0, 0, -1});  // end-on
  EXPECT_EQ(count_pixels(points.image(), white), 160 * 120);
}

TEST(Rasterizer, RejectsInvalidIndicesAndStylesBeforeDrawing) {
  Rasterizer rasterizer(camera_on_z(5.0), white);
  const VertexMatrix vertices = rows({{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}});
  const TriangleMatrix triangles{{0, 1, 2}, {0, 1, 3}};
  try {
    rasterizer.draw_mesh(vertices, triangles);
    ADD_FAILURE() << "no exception";
  } catch (const reduced::MeshError& error) {
    EXPECT_EQ(error.element(), 1);
    EXPECT_NE(std::string(error.what()).find("triangle 1"), std::string::npos) << error.what();
  }
  EXPECT_THROW(rasterizer.draw_mesh(vertices, TriangleMatrix{{0, -1, 2}}), reduced::MeshError);
  EXPECT_THROW(rasterizer.draw_mesh(vertices, TriangleMatrix{{0, 1, 2}}, {.ambient = 1.5}),
               reduced::Error);
  // Nothing was drawn by the failed calls (the first triangle was valid).
  EXPECT_EQ(count_pixels(rasterizer.image(), white), 160 * 120);

  const std::vector<Color> two{red, blue};
  EXPECT_NE(thrown_message<reduced::Error>([&] {
              rasterizer.draw_points(vertices, two);
            }).find("2 colours for 3 points"),
            std::string::npos);
  const std::vector<Color> one{red};
  EXPECT_THROW(rasterizer.draw_points(vertices, one, {.radius = 0.0}), reduced::Error);
  EXPECT_THROW(rasterizer.draw_arrow({0, 0, 0}, {1, 0, 0}, {.width = nan}), reduced::Error);
  EXPECT_THROW(rasterizer.draw_arrow({0, 0, 0}, {1, 0, 0}, {.head_length = -1.0}), reduced::Error);
}

TEST(Rasterizer, ClearResetsImageAndDepth) {
  const Sphere sphere = icosphere(2, 1.0, Eigen::Vector3d::Zero());
  Rasterizer rasterizer(camera_on_z(5.0), white);
  rasterizer.draw_mesh(sphere.vertices, sphere.triangles);
  rasterizer.clear(blue);
  EXPECT_EQ(count_pixels(rasterizer.image(), blue), 160 * 120);
  EXPECT_EQ(rasterizer.depth(80, 60), std::numeric_limits<double>::infinity());
  // A far point draws where the sphere was: the old depth is gone.
  const std::vector<Color> one{red};
  rasterizer.draw_points(rows({{0, 0, -3}}), one);
  EXPECT_EQ(rasterizer.image().pixel(80, 60), red);
}

// --- Points ------------------------------------------------------------------------------------

TEST(Rasterizer, PointsInFrontOfTheSurfaceShowAndPointsBehindItDoNot) {
  const Camera camera = camera_on_z(4.0);
  const Sphere sphere = icosphere(3, 1.0, Eigen::Vector3d::Zero());
  const std::vector<Color> one{red};
  const Eigen::Vector3d in_front(0.2, 0.1, 1.2), on_surface(0.0, 0.6, 0.8), behind(-0.2, 0.1, -1.2),
      beside(1.6, 0.0, -1.2);

  Rasterizer rasterizer(camera, white);
  rasterizer.draw_mesh(sphere.vertices, sphere.triangles, {.color = grey, .ambient = 1.0});
  rasterizer.draw_points(rows({behind}), one, {.radius = 3.0});
  EXPECT_EQ(count_pixels(rasterizer.image(), red), 0);
  EXPECT_EQ(pixel_at(rasterizer.image(), *camera.project(behind)), grey);

  rasterizer.draw_points(rows({in_front, on_surface, beside}), one, {.radius = 3.0});
  for (const Eigen::Vector3d& point : {in_front, on_surface, beside}) {
    EXPECT_EQ(pixel_at(rasterizer.image(), *camera.project(point)), red) << point.transpose();
  }
  // Three discs of radius 3: about 3 · 9π pixels, none of them lost to the surface.
  EXPECT_NEAR(count_pixels(rasterizer.image(), red), 3 * 9 * std::numbers::pi, 12);
}

TEST(Rasterizer, PointsTakeTheirOwnColours) {
  const Camera camera = camera_on_z(4.0);
  const VertexMatrix points = rows({{-1, 0, 0}, {0, 0, 0}, {1, 0, 0}});
  const std::vector<Color> colors{red, blue, grey};
  Rasterizer rasterizer(camera, white);
  rasterizer.draw_points(points, colors, {.radius = 2.0});
  for (Eigen::Index i = 0; i < 3; ++i) {
    EXPECT_EQ(pixel_at(rasterizer.image(), *camera.project(points.row(i).transpose())),
              colors[static_cast<std::size_t>(i)]);
  }
  // A sub-pixel radius still marks the pixel containing the point.
  Rasterizer tiny(camera, white);
  const std::vector<Color> one{red};
  tiny.draw_points(rows({{0.01, 0.02, 0}}), one, {.radius = 0.1});
  EXPECT_EQ(count_pixels(tiny.image(), red), 1);
  EXPECT_EQ(pixel_at(tiny.image(), *camera.project({0.01, 0.02, 0})), red);
}

// --- Arrows ------------------------------------------------------------------------------------

TEST(Rasterizer, ArrowPixelsLieAlongItsProjectedDirectionWithTheHeadAtTheTip) {
  const Camera camera = camera_on_z(10.0, 320, 240);
  const Eigen::Vector3d tail(-2.0, -1.0, 0.5), tip(2.0, 1.0, -0.5);
  const ArrowStyle style{.color = red, .width = 3.0, .head_length = 20.0, .head_width = 14.0};
  Rasterizer rasterizer(camera, white);
  rasterizer.draw_arrow(tail, tip, style);

  const Eigen::Vector2d p0 = camera.project(tail)->pixel, p1 = camera.project(tip)->pixel;
  const double length = (p1 - p0).norm();
  const Eigen::Vector2d along = (p1 - p0) / length;
  double min_along = length, max_along = 0.0, widest_shaft = 0.0, widest_head = 0.0;
  int count = 0;
  for (int y = 0; y < 240; ++y) {
    for (int x = 0; x < 320; ++x) {
      if (rasterizer.image().pixel(x, y) != red) continue;
      ++count;
      const Eigen::Vector2d d = Eigen::Vector2d(x + 0.5, y + 0.5) - p0;
      const double s = d.dot(along);
      const double across = std::abs(d.x() * along.y() - d.y() * along.x());
      min_along = std::min(min_along, s);
      max_along = std::max(max_along, s);
      if (s < length - style.head_length - 1.0) {
        widest_shaft = std::max(widest_shaft, across);
      } else {
        widest_head = std::max(widest_head, across);
      }
    }
  }
  ASSERT_GT(count, 0);
  // From tail to tip, and nowhere else.
  EXPECT_LT(min_along, 1.0);
  EXPECT_GT(max_along, length - 2.0);
  EXPECT_LT(max_along, length + 0.5);
  EXPECT_LE(widest_shaft, style.width / 2.0 + 0.01);
  EXPECT_LE(widest_head, style.head_width / 2.0 + 0.01);
  EXPECT_GT(widest_head, style.head_width / 2.0 - 1.5);
}

TEST(Rasterizer, ArrowsAreDepthTestedUnlessAlwaysOnTop) {
  const Camera camera = camera_on_z(4.0);
  const Sphere sphere = icosphere(3, 1.0, Eigen::Vector3d::Zero());
  const Eigen::Vector3d tail(-0.5, 0.0, -2.0), tip(0.5, 0.0, -2.0);  // behind the sphere
  for (const bool on_top : {false, true}) {
    Rasterizer rasterizer(camera, white);
    rasterizer.draw_mesh(sphere.vertices, sphere.triangles, {.color = grey, .ambient = 1.0});
    rasterizer.draw_arrow(tail, tip, {.color = red, .always_on_top = on_top});
    EXPECT_EQ(count_pixels(rasterizer.image(), red) > 0, on_top);
    // An always-on-top arrow leaves the depth buffer to the sphere.
    EXPECT_NEAR(rasterizer.depth(80, 60), 3.0, 0.01);
  }
  // In front of the sphere, a depth-tested arrow shows and hides the sphere.
  Rasterizer rasterizer(camera, white);
  rasterizer.draw_mesh(sphere.vertices, sphere.triangles, {.color = grey, .ambient = 1.0});
  rasterizer.draw_arrow({-0.5, 0.0, 1.5}, {0.5, 0.0, 1.5}, {.color = red});
  EXPECT_EQ(rasterizer.image().pixel(80, 60), red);
}

// --- PNG files ---------------------------------------------------------------------------------

TEST(PngFile, RoundTripKeepsSizeAndEveryPixel) {
  Image image(37, 23);
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) {
      image.set_pixel(x, y,
                      {static_cast<std::uint8_t>(7 * x), static_cast<std::uint8_t>(11 * y),
                       static_cast<std::uint8_t>((x * y) % 256)});
    }
  }
  const std::filesystem::path file = "test_tools_render_round_trip.png";
  write_png(image, file);
  const Image back = read_png(file);
  std::filesystem::remove(file);
  EXPECT_EQ(back.width(), 37);
  EXPECT_EQ(back.height(), 23);
  EXPECT_TRUE(back == image);
}

TEST(PngFile, WritingToAnImpossiblePathNamesIt) {
  const std::string path = "/nonexistent-khz-directory/sub/picture.png";
  const std::string message =
      thrown_message<reduced::IoError>([&] { write_png(Image(4, 4), path); });
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find("cannot open for writing"), std::string::npos) << message;
}

TEST(PngFile, ReadingMissingOrMalformedFilesNamesThem) {
  const std::string missing = "test_tools_render_missing.png";
  EXPECT_NE(thrown_message<reduced::IoError>([&] { read_png(missing); }).find(missing),
            std::string::npos);

  const std::filesystem::path text = "test_tools_render_not_a.png";
  std::ofstream(text) << "not a PNG file\n";
  const std::string message = thrown_message<reduced::Error>([&] { read_png(text); });
  std::filesystem::remove(text);
  EXPECT_NE(message.find(text.string()), std::string::npos) << message;
  EXPECT_NE(message.find("not a readable PNG"), std::string::npos) << message;
}

}  // namespace
}  // namespace khz::render
