#include <khz/reduced/basis/force_load.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <array>
#include <limits>
#include <string>
#include <vector>

namespace khz::reduced {
namespace {

constexpr Eigen::Index num_vertices = 10;

PointForce point(int vertex, double x, double y, double z) {
  return PointForce{vertex, Eigen::Vector3d(x, y, z)};
}

std::vector<ForceLoad> sample_loads() {
  return {
      ForceLoad{{point(9, 0.0, 0.0, -15.5), point(8, 0.0, 0.0, -15.5)}},
      ForceLoad{{point(0, 1.0 / 3.0, -2.5e-300, 7e22)}},
      ForceLoad{{point(4, -0.1, 0.2, 0.3), point(4, 1.0, 1.0, 1.0), point(5, 2.0, 0.0, 0.0)}},
  };
}

void expect_same_loads(const std::vector<ForceLoad>& a, const std::vector<ForceLoad>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t l = 0; l < a.size(); ++l) {
    ASSERT_EQ(a[l].forces.size(), b[l].forces.size()) << "load " << l;
    for (std::size_t p = 0; p < a[l].forces.size(); ++p) {
      EXPECT_EQ(a[l].forces[p].vertex, b[l].forces[p].vertex) << "load " << l << " force " << p;
      EXPECT_EQ(a[l].forces[p].force, b[l].forces[p].force) << "load " << l << " force " << p;
    }
  }
}

TEST(ForceLoad, FormatsOneRowPerPointForce) {
  const std::vector<ForceLoad> loads = {ForceLoad{{point(9, 0, 0, -15.5), point(8, 1, 0, 0)}},
                                        ForceLoad{{point(3, 0.1, 2, -3)}}};
  EXPECT_EQ(format_force_loads(loads),
            "load,vertex,fx,fy,fz\n"
            "0,9,0,0,-15.5\n"
            "0,8,1,0,0\n"
            "1,3,0.1,2,-3\n");
}

TEST(ForceLoad, RoundTripsThroughAFileExactly) {
  const std::vector<ForceLoad> loads = sample_loads();
  const std::filesystem::path file = test::scratch_file("loads.csv");
  write_force_loads(file, loads);
  expect_same_loads(read_force_loads(file, num_vertices), loads);
}

TEST(ForceLoad, ReadsPaddingCommentsBlankLinesCrlfAndByteOrderMark) {
  const std::string text =
      "\xEF\xBB\xBF# recorded by hand\r\n"
      " load , vertex,fx ,fy,\tfz\r\n"
      "\r\n"
      "0, 3, 1.5, 0, -2\r\n"
      "  # a comment between loads\n"
      "1,4,+1e3,0,0";
  const std::vector<ForceLoad> loads = parse_force_loads(text, "loads.csv", num_vertices);
  expect_same_loads(loads, {ForceLoad{{point(3, 1.5, 0, -2)}}, ForceLoad{{point(4, 1e3, 0, 0)}}});
}

TEST(ForceLoad, HeaderAloneIsAnEmptyRecording) {
  EXPECT_TRUE(parse_force_loads("load,vertex,fx,fy,fz\n", "loads.csv", num_vertices).empty());
}

struct MalformedText {
  const char* text;
  const char* message;
};

TEST(ForceLoad, RejectsMalformedLinesWithFileAndLine) {
  const MalformedText cases[] = {
      {"", "loads.csv:1: file ends early: expected the header 'load,vertex,fx,fy,fz'"},
      {"# only a comment\n", "loads.csv:2: file ends early: expected the header"},
      {"load,vertex,fx,fy\n0,1,2,3\n",
       "loads.csv:1: expected the header 'load,vertex,fx,fy,fz', found 'load,vertex,fx,fy'"},
      {"vertex,load,fx,fy,fz\n", "loads.csv:1: expected the header 'load,vertex,fx,fy,fz'"},
      {"load,vertex,fx,fy,fz\n0,1,2,3\n",
       "loads.csv:2: expected 5 comma-separated fields 'load,vertex,fx,fy,fz', found 4"},
      {"load,vertex,fx,fy,fz\n0,1,2,3,4,\n",
       "loads.csv:2: expected 5 comma-separated fields 'load,vertex,fx,fy,fz', found 6"},
      {"load,vertex,fx,fy,fz\n0 1 2 3 4\n",
       "loads.csv:2: expected 5 comma-separated fields 'load,vertex,fx,fy,fz', found 1"},
      {"load,vertex,fx,fy,fz\nA,1,2,3,4\n",
       "loads.csv:2: expected a load id (an integer), found 'A'"},
      {"load,vertex,fx,fy,fz\n1,1,2,3,4\n",
       "loads.csv:2: load id 1 is out of sequence: expected 0 (ids count up from 0 and the rows "
       "of a load are consecutive)"},
      // The first load's id is 0, not −1 (found by fuzz_loads: it read an empty load list).
      {"load,vertex,fx,fy,fz\n-1,1,0,0,-1\n",
       "loads.csv:2: load id -1 is out of sequence: expected 0"},
      {"load,vertex,fx,fy,fz\n0,1,2,3,4\n\n2,1,2,3,4\n",
       "loads.csv:4: load id 2 is out of sequence: expected 0 or 1"},
      {"load,vertex,fx,fy,fz\n0,1,0,0,1\n1,1,0,0,1\n0,2,0,0,1\n",
       "loads.csv:4: load id 0 is out of sequence: expected 1 or 2"},
      {"load,vertex,fx,fy,fz\n0,1.5,2,3,4\n",
       "loads.csv:2: expected a vertex index (an integer), found '1.5'"},
      {"load,vertex,fx,fy,fz\n0,10,2,3,4\n",
       "loads.csv:2: vertex 10 is out of range: the mesh has 10 vertices"},
      {"load,vertex,fx,fy,fz\n0,-1,2,3,4\n",
       "loads.csv:2: vertex -1 is out of range: the mesh has 10 vertices"},
      {"load,vertex,fx,fy,fz\n0,1,,3,4\n",
       "loads.csv:2: expected force component fx (a finite number), found ''"},
      {"load,vertex,fx,fy,fz\n0,1,2,inf,4\n",
       "loads.csv:2: expected force component fy (a finite number), found 'inf'"},
      {"load,vertex,fx,fy,fz\n0,1,2,3,nan\n",
       "loads.csv:2: expected force component fz (a finite number), found 'nan'"},
      {"load,vertex,fx,fy,fz\n0,1,2,3,1e999\n",
       "loads.csv:2: expected force component fz (a finite number), found '1e999'"},
      {"load,vertex,fx,fy,fz\n0,1,2,3,4 N\n",
       "loads.csv:2: expected force component fz (a finite number), found '4 N'"},
  };
  for (const MalformedText& c : cases) {
    SCOPED_TRACE(c.text);
    EXPECT_TRUE(test::throws_with_message<ParseError>(
        [&] { parse_force_loads(c.text, "loads.csv", num_vertices); }, c.message));
  }
}

// The committed malformed corpus, which the fuzz run reads too.
TEST(ForceLoad, RejectsTheMalformedCorpus) {
  const std::array<test::MalformedFile, 1> cases{{
      {"first_id_minus_one.csv",
       "first_id_minus_one.csv:2: load id -1 is out of sequence: expected 0"},
  }};
  test::expect_corpus_rejected("malformed/loads", cases, [](const std::filesystem::path& file) {
    read_force_loads(file, num_vertices);
  });
}

TEST(ForceLoad, ParseErrorCarriesTheLine) {
  try {
    parse_force_loads("load,vertex,fx,fy,fz\n0,1,2,3,4\n0,99,2,3,4\n", "loads.csv", num_vertices);
    FAIL() << "did not throw";
  } catch (const ParseError& error) {
    EXPECT_EQ(error.source(), "loads.csv");
    EXPECT_EQ(error.line(), 3);
  }
}

TEST(ForceLoad, MissingFileIsAnIoError) {
  EXPECT_THROW(read_force_loads(test::scratch_file("absent.csv"), num_vertices), IoError);
}

TEST(ForceLoad, EmptyOrNonFiniteLoadCannotBeWritten) {
  const std::vector<ForceLoad> with_empty = {ForceLoad{{point(1, 0, 0, 1)}}, ForceLoad{}};
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] { format_force_loads(with_empty); },
      "format_force_loads: load 1 has no point forces; the load file cannot represent an empty "
      "load"));
  const std::vector<ForceLoad> with_nan = {
      ForceLoad{{point(1, 0, std::numeric_limits<double>::quiet_NaN(), 1)}}};
  EXPECT_TRUE(test::throws_with_message<Error>([&] { format_force_loads(with_nan); },
                                               "format_force_loads: load 0 has a non-finite"));
}

TEST(ForceLoad, FullVectorAddsRepeatedVertices) {
  const ForceLoad load = sample_loads()[2];
  const Eigen::VectorXd f = load.to_vector(num_vertices);
  ASSERT_EQ(f.size(), 3 * num_vertices);
  EXPECT_EQ(f.segment<3>(12), Eigen::Vector3d(-0.1, 0.2, 0.3) + Eigen::Vector3d(1.0, 1.0, 1.0));
  EXPECT_EQ(f.segment<3>(15), Eigen::Vector3d(2.0, 0.0, 0.0));
  EXPECT_EQ((f.array() != 0.0).count(), 4);
  EXPECT_EQ(ForceLoad{}.to_vector(num_vertices), Eigen::VectorXd::Zero(3 * num_vertices));
}

TEST(ForceLoad, ValidateNamesThePointForce) {
  const ForceLoad outside{{point(1, 0, 0, 1), point(10, 0, 0, 1)}};
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] { outside.to_vector(num_vertices); },
      "point force 1 acts on vertex 10, but the mesh has 10 vertices"));
  const ForceLoad infinite{{point(2, 0, std::numeric_limits<double>::infinity(), 1)}};
  EXPECT_TRUE(test::throws_with_message<Error>([&] { infinite.validate(num_vertices); },
                                               "point force 0 (vertex 2) is not finite"));
}

TEST(ForceLoad, DistancesAreExactNormsOfFullVectorDifferences) {
  std::vector<ForceLoad> loads = sample_loads();
  // loads[2] with its repeated vertex summed: the same full vector.
  loads[1] = ForceLoad{{point(5, 2.0, 0.0, 0.0), point(4, -0.1 + 1.0, 0.2 + 1.0, 0.3 + 1.0)}};
  loads.push_back(ForceLoad{{point(5, 1.0, 0.0, 0.0)}});
  loads.push_back(ForceLoad{});
  const Eigen::MatrixXd d = force_distances(loads);
  ASSERT_EQ(d.rows(), 5);
  ASSERT_EQ(d.cols(), 5);
  EXPECT_EQ(d, d.transpose());
  EXPECT_EQ(d.diagonal(), Eigen::VectorXd::Zero(5));
  // The same load written differently (a repeated vertex summed) is at distance 0.
  EXPECT_EQ(d(1, 2), 0.0);
  for (Eigen::Index i = 0; i < 5; ++i) {
    for (Eigen::Index j = 0; j < 5; ++j) {
      const double expected = (loads[static_cast<std::size_t>(i)].to_vector(num_vertices) -
                               loads[static_cast<std::size_t>(j)].to_vector(num_vertices))
                                  .norm();
      EXPECT_NEAR(d(i, j), expected, 1e-14 * expected) << i << ", " << j;
    }
  }
  EXPECT_TRUE(force_distances({}).size() == 0);
}

}  // namespace
}  // namespace khz::reduced
