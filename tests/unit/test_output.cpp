// io/output: the files a user opens in ParaView or a spreadsheet, checked byte by byte.
// VtuSample also leaves a known file for tests/scripts/test_vtk_readback.sh to read with VTK.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <regex>
#include <sstream>
#include <string>

#include "spall/io/output/history.hpp"
#include "spall/io/output/run_info.hpp"
#include "spall/io/output/vtu.hpp"

namespace {

namespace fs = std::filesystem;
using namespace spall::io::output;
using spall::Vec3;
using spall::discretization::Field;
using spall::discretization::symmetric_tensor_components;

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream contents;
  contents << in.rdbuf();
  return contents.str();
}

class OutputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    directory_ = fs::path(::testing::TempDir()) /
                 (std::string("spall_output_") + test->name() + "_" + std::to_string(::getpid()));
    fs::remove_all(directory_);
    fs::create_directories(directory_);
  }
  void TearDown() override { fs::remove_all(directory_); }
  fs::path directory_;
};

// A VTU file taken apart: the XML up to the '_' that starts the appended data, every DataArray's
// attributes, and the raw appended bytes.
struct ParsedVtu {
  std::string xml;
  std::vector<std::map<std::string, std::string>> arrays;
  std::string appended;  // from just after '_' to the end of the file

  const std::map<std::string, std::string>& array(const std::string& name) const {
    for (const auto& attributes : arrays) {
      if (attributes.count("Name") ? attributes.at("Name") == name : name.empty()) return attributes;
    }
    throw std::runtime_error("no DataArray " + name);
  }

  // The values of one appended block, after its UInt64 byte count.
  template <class T>
  std::vector<T> values(const std::string& name) const {
    const std::size_t offset = std::stoull(array(name).at("offset"));
    std::uint64_t bytes = 0;
    std::memcpy(&bytes, appended.data() + offset, sizeof bytes);
    std::vector<T> decoded(bytes / sizeof(T));
    // An empty vector's data() may be null, and memcpy from or to null is undefined even for 0 bytes.
    if (bytes > 0) std::memcpy(decoded.data(), appended.data() + offset + sizeof bytes, bytes);
    return decoded;
  }
};

ParsedVtu parse_vtu(const std::string& file) {
  ParsedVtu vtu;
  const std::string appended_tag = R"(<AppendedData encoding="raw">)";
  const std::size_t tag = file.find(appended_tag);
  EXPECT_NE(tag, std::string::npos);
  const std::size_t underscore = file.find('_', tag + appended_tag.size());
  EXPECT_NE(underscore, std::string::npos);
  vtu.xml = file.substr(0, underscore);
  vtu.appended = file.substr(underscore + 1);

  const std::regex data_array(R"(<DataArray([^>]*)/>)");
  const std::regex attribute(R"#(\s(\w+)="([^"]*)")#");
  for (auto it = std::sregex_iterator(vtu.xml.begin(), vtu.xml.end(), data_array);
       it != std::sregex_iterator(); ++it) {
    const std::string text = (*it)[1];
    std::map<std::string, std::string> attributes;
    for (auto a = std::sregex_iterator(text.begin(), text.end(), attribute);
         a != std::sregex_iterator(); ++a) {
      attributes[(*a)[1]] = (*a)[2];
    }
    vtu.arrays.push_back(attributes);
  }
  return vtu;
}

std::size_t bytes_per_value(const std::string& type) {
  if (type == "Float64" || type == "Int64") return 8;
  if (type == "UInt8") return 1;
  throw std::runtime_error("unexpected type " + type);
}

const std::vector<Vec3> awkward_points = {
    {0.1, -0.0, 1e-310},  // 1e-310 is subnormal: no text round trip may touch it
    {std::numeric_limits<double>::max(), -1.0 / 3.0, 2.5},
    {-7.0, std::numeric_limits<double>::min(), 6.02214076e23}};

TEST_F(OutputTest, VtuAppendedBlocksAddUpToTheFileSize) {
  const std::vector<Field> fields{
      {"velocity", 3, std::vector<double>(9, 1.0)},
      {"stress", 6, std::vector<double>(18, 2.0), symmetric_tensor_components},
      {"category", 1, std::vector<std::int64_t>{0, 1, 2}}};
  const fs::path path = directory_ / "state.vtu";
  write_vtu(path, awkward_points, fields);

  const std::string file = read_file(path);
  const ParsedVtu vtu = parse_vtu(file);
  EXPECT_NE(vtu.xml.find(R"(<VTKFile type="UnstructuredGrid" version="1.0" )"
                         R"(byte_order="LittleEndian" header_type="UInt64">)"),
            std::string::npos);
  EXPECT_NE(vtu.xml.find(R"(<Piece NumberOfPoints="3" NumberOfCells="3">)"), std::string::npos);
  ASSERT_EQ(vtu.arrays.size(), 3u + 1u + 3u);  // fields, points, three cell arrays

  // In offset order, every block is a UInt64 byte count and exactly that many bytes, and the
  // next block starts right after it.
  std::size_t expected_offset = 0;
  for (const auto& attributes : vtu.arrays) {
    ASSERT_EQ(attributes.at("format"), "appended");
    ASSERT_EQ(std::stoull(attributes.at("offset")), expected_offset);
    std::uint64_t bytes = 0;
    ASSERT_LE(expected_offset + sizeof bytes, vtu.appended.size());
    std::memcpy(&bytes, vtu.appended.data() + expected_offset, sizeof bytes);
    const std::size_t components = std::stoull(attributes.at("NumberOfComponents"));
    EXPECT_EQ(bytes, 3 * components * bytes_per_value(attributes.at("type")));
    expected_offset += sizeof bytes + bytes;
  }
  const std::string closing = "\n  </AppendedData>\n</VTKFile>\n";
  EXPECT_EQ(vtu.xml.size() + 1 + expected_offset + closing.size(), file.size());
  EXPECT_EQ(file.substr(file.size() - closing.size()), closing);

  EXPECT_EQ(vtu.array("stress").at("ComponentName0"), "xx");
  EXPECT_EQ(vtu.array("stress").at("ComponentName5"), "zx");
}

TEST_F(OutputTest, VtuPointsDecodeBitExactly) {
  const fs::path path = directory_ / "points.vtu";
  write_vtu(path, awkward_points, {});
  const ParsedVtu vtu = parse_vtu(read_file(path));
  const auto coordinates = vtu.values<double>("");
  ASSERT_EQ(coordinates.size(), 9u);
  EXPECT_EQ(std::memcmp(coordinates.data(), awkward_points.data(), 9 * sizeof(double)), 0);
  EXPECT_EQ(vtu.array("").at("type"), "Float64");
}

TEST_F(OutputTest, VtuFieldsAndVertexCellsDecode) {
  const std::vector<std::int64_t> category{-1, 9'007'199'254'740'993, 2};  // 2^53 + 1: not a double
  const std::vector<double> velocity{1, 2, 3, 4, 5, 6, 7, 8, 9};
  const fs::path path = directory_ / "fields.vtu";
  write_vtu(path, awkward_points, {{"velocity", 3, velocity}, {"category", 1, category}});
  const ParsedVtu vtu = parse_vtu(read_file(path));

  EXPECT_EQ(vtu.values<double>("velocity"), velocity);
  EXPECT_EQ(vtu.values<std::int64_t>("category"), category);
  EXPECT_EQ(vtu.array("category").at("type"), "Int64");
  EXPECT_EQ(vtu.values<std::int64_t>("connectivity"), (std::vector<std::int64_t>{0, 1, 2}));
  EXPECT_EQ(vtu.values<std::int64_t>("offsets"), (std::vector<std::int64_t>{1, 2, 3}));
  EXPECT_EQ(vtu.values<std::uint8_t>("types"), (std::vector<std::uint8_t>{1, 1, 1}));
}

TEST_F(OutputTest, VtuWithNoPointsIsWellFormed) {
  const fs::path path = directory_ / "empty.vtu";
  write_vtu(path, {}, {{"pressure", 1, std::vector<double>{}}});
  const std::string file = read_file(path);
  const ParsedVtu vtu = parse_vtu(file);
  EXPECT_NE(vtu.xml.find(R"(NumberOfPoints="0")"), std::string::npos);
  EXPECT_EQ(vtu.values<double>("pressure").size(), 0u);
  EXPECT_EQ(vtu.appended.size(), 5 * sizeof(std::uint64_t) + std::strlen("\n  </AppendedData>\n</VTKFile>\n"));
}

TEST_F(OutputTest, VtuRejectsFieldsThatDoNotFitThePoints) {
  const fs::path path = directory_ / "bad.vtu";
  EXPECT_THROW(write_vtu(path, awkward_points, {{"velocity", 3, std::vector<double>(8)}}),
               std::invalid_argument);
  EXPECT_THROW(write_vtu(path, awkward_points,
                         {{"stress", 6, std::vector<double>(18), {"xx", "yy"}}}),
               std::invalid_argument);
  EXPECT_THROW(write_vtu(path, awkward_points,
                         {{"pressure", 1, std::vector<double>(3)}, {"pressure", 1, std::vector<double>(3)}}),
               std::invalid_argument);
  EXPECT_FALSE(fs::exists(path));
}

TEST_F(OutputTest, VtuUnwritablePathThrowsNamingThePath) {
  const fs::path path = directory_ / "no_such_directory" / "state.vtu";
  try {
    write_vtu(path, awkward_points, {});
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(path.string()), std::string::npos) << error.what();
  }
}

TEST_F(OutputTest, VtuReplacesAnEarlierFileAndLeavesNoTemporary) {
  const fs::path path = directory_ / "state.vtu";
  write_vtu(path, awkward_points, {});
  write_vtu(path, {Vec3(1, 2, 3)}, {});
  EXPECT_NE(read_file(path).find(R"(NumberOfPoints="1")"), std::string::npos);
  EXPECT_EQ(std::distance(fs::directory_iterator(directory_), fs::directory_iterator()), 1);
}

TEST_F(OutputTest, PvdListsDatasetsInOrderWithFullPrecisionTimes) {
  const fs::path path = directory_ / "particles.pvd";
  PvdSeries series(path);
  series.add(0.0, "particles_0000.vtu");
  series.add(0.1, "particles_0001.vtu");
  EXPECT_NE(read_file(path).find("particles_0001.vtu"), std::string::npos)
      << "rewritten on every add";
  series.add(1.0 / 3.0, "particles_0002.vtu");

  const std::string pvd = read_file(path);
  EXPECT_NE(pvd.find(R"(<VTKFile type="Collection" version="1.0")"), std::string::npos);
  const std::regex dataset(R"#(<DataSet timestep="([^"]*)"[^>]* file="([^"]*)"/>)#");
  std::vector<std::pair<std::string, std::string>> listed;
  for (auto it = std::sregex_iterator(pvd.begin(), pvd.end(), dataset); it != std::sregex_iterator(); ++it) {
    listed.emplace_back((*it)[1], (*it)[2]);
  }
  const std::vector<std::pair<std::string, std::string>> expected{
      {"0", "particles_0000.vtu"},
      {"0.10000000000000001", "particles_0001.vtu"},
      {"0.33333333333333331", "particles_0002.vtu"}};
  EXPECT_EQ(listed, expected);
  EXPECT_EQ(std::stod(listed[2].first), 1.0 / 3.0);
}

TEST_F(OutputTest, CsvHeaderHasUnitsAndRowsAreFlushedAtOnce) {
  const fs::path path = directory_ / "glstat.csv";
  CsvHistory history(path, {{"time", "s"}, {"dt", "s"}, {"kinetic_energy", "J"}, {"cycle", ""}});
  EXPECT_EQ(read_file(path), "time [s],dt [s],kinetic_energy [J],cycle\n");
  const std::vector<double> row{1.0 / 3.0, 1e-7, -12345678901.5, 42};
  history.append(row);
  // Read while the history is still open: a crash after append must not lose the row.
  EXPECT_EQ(read_file(path),
            "time [s],dt [s],kinetic_energy [J],cycle\n"
            "0.3333333333,1e-07,-1.23456789e+10,42\n");
}

TEST_F(OutputTest, CsvQuotesHeadingsThatWouldSplitAColumn) {
  const fs::path path = directory_ / "rcforc.csv";
  CsvHistory history(path, {{"force x, tool", "N"}, {"say \"hi\"", ""}});
  EXPECT_EQ(read_file(path), "\"force x, tool [N]\",\"say \"\"hi\"\"\"\n");
}

TEST_F(OutputTest, CsvRejectsARowOfTheWrongLength) {
  CsvHistory history(directory_ / "matsum.csv", {{"time", "s"}, {"internal_energy", "J"}});
  const std::vector<double> short_row{1.0};
  EXPECT_THROW(history.append(short_row), std::invalid_argument);
  EXPECT_EQ(read_file(directory_ / "matsum.csv"), "time [s],internal_energy [J]\n");
}

TEST_F(OutputTest, CsvUnwritablePathThrowsNamingThePath) {
  const fs::path path = directory_ / "no_such_directory" / "glstat.csv";
  try {
    CsvHistory history(path, {{"time", "s"}});
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(path.string()), std::string::npos) << error.what();
  }
}

TEST_F(OutputTest, RunJsonEscapesStrings) {
  const fs::path path = directory_ / "run.json";
  RunInfo info;
  info.version = "0.1.0";
  info.deck = "C:\\decks\\\"taylor\" bar\n\t\x01.k";
  info.threads = 2;
  info.ranks = 4;
  info.rebalances = 7;
  info.halo = "by reach";
  info.received_bytes_mean = 1.5e6;
  info.received_bytes_max = 2097152;
  info.communicating_seconds_mean = 0.5;
  info.communicating_seconds_max = 0.75;
  info.node_rows_mean = 412.5;
  info.node_rows_max = 530;
  info.peak_resident_bytes_mean = 1.25e8;
  info.peak_resident_bytes_max = 130023424;
  info.steps = 123456789012LL;
  info.end_time = 0.1;
  info.wall_seconds = std::numeric_limits<double>::quiet_NaN();
  info.nodes = 1000;
  info.initial_mass = 2.5;
  info.masses = {{"added_mass", 0.5}};
  info.status = "completed";
  info.phases = {{"internal_forces", 1.5}, {"output", 0.25}};
  write_run_json(path, info);
  EXPECT_EQ(read_file(path),
            "{\n"
            "  \"version\": \"0.1.0\",\n"
            "  \"deck\": \"C:\\\\decks\\\\\\\"taylor\\\" bar\\n\\t\\u0001.k\",\n"
            "  \"threads\": 2,\n"
            "  \"ranks\": 4,\n"
            "  \"rebalances\": 7,\n"
            "  \"halo\": \"by reach\",\n"
            "  \"received_bytes_per_step\": {\"mean\": 1500000, \"max\": 2097152},\n"
            "  \"communicating_seconds\": {\"mean\": 0.5, \"max\": 0.75},\n"
            "  \"node_rows\": {\"mean\": 412.5, \"max\": 530},\n"
            "  \"peak_resident_bytes\": {\"mean\": 125000000, \"max\": 130023424},\n"
            "  \"steps\": 123456789012,\n"
            "  \"end_time\": 0.10000000000000001,\n"
            "  \"wall_seconds\": null,\n"
            "  \"nodes\": 1000,\n"
            "  \"mass\": {\"initial\": 2.5, \"added_mass\": 0.5},\n"
            "  \"phases\": {\"internal_forces\": 1.5, \"output\": 0.25},\n"
            "  \"energy_ratio\": null,\n"
            "  \"status\": \"completed\"\n"
            "}\n");
}

// The files tests/scripts/test_vtk_readback.sh reads with VTK's own reader: written to
// $SPALL_VTU_SAMPLE_DIR when set. The script knows these values; change both together.
TEST(VtuSample, WritesTheSampleForTheVtkReadbackScript) {
  const char* sample_directory = std::getenv("SPALL_VTU_SAMPLE_DIR");
  const fs::path directory = sample_directory ? fs::path(sample_directory) : fs::path(::testing::TempDir());
  const std::vector<Vec3> points{{0, 0, 0}, {0.1, -2.5, 3}, {1e-310, 7, -0.0}, {4, 5, 6}};
  const std::vector<Field> fields{
      {"velocity", 3, std::vector<double>{1.5, -2, 0.1, 0, 0, 0, -3.25, 4, 1e-3, 7, 8, 9}},
      {"category", 1, std::vector<std::int64_t>{0, 2, -1, 9'007'199'254'740'993}},
      {"stress", 6, std::vector<double>(24, -1e6), symmetric_tensor_components}};
  const fs::path path = directory / "sample.vtu";
  write_vtu(path, points, fields);
  PvdSeries series(directory / "sample.pvd");
  series.add(0.1, "sample.vtu");
  EXPECT_TRUE(fs::exists(path));
  if (!sample_directory) {  // nobody is going to read them
    fs::remove(path);
    fs::remove(directory / "sample.pvd");
  }
}

// A unit cube as 8 points and one hexahedron (VTK's node order: the bottom face counter-clockwise
// seen from above, then the top face), with a point field and a cell field that only the
// hexahedron has: the vertex cells hold the fill value. test_vtk_readback.sh reads it with VTK.
TEST(VtuSample, WritesTheHexahedronSampleForTheVtkReadbackScript) {
  const char* sample_directory = std::getenv("SPALL_VTU_SAMPLE_DIR");
  const fs::path directory = sample_directory ? fs::path(sample_directory) : fs::path(::testing::TempDir());
  const std::vector<Vec3> points{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                 {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const std::vector<Field> fields{{"node_id", 1, std::vector<std::int64_t>{1, 2, 3, 4, 5, 6, 7, 8}}};
  spall::discretization::CellBlock hexahedra;
  hexahedra.connectivity = {0, 1, 2, 3, 4, 5, 6, 7};
  hexahedra.fields.push_back({"element_id", 1, std::vector<std::int64_t>{42}});
  hexahedra.fields.push_back({"plastic_strain", 1, std::vector<double>{0.25}});
  const fs::path path = directory / "hexahedron.vtu";
  write_vtu(path, points, fields, {hexahedra});
  const ParsedVtu vtu = parse_vtu(read_file(path));
  EXPECT_NE(vtu.xml.find(R"(<Piece NumberOfPoints="8" NumberOfCells="9">)"), std::string::npos);
  EXPECT_NE(vtu.xml.find("<CellData>"), std::string::npos);
  if (!sample_directory) fs::remove(path);
}

TEST(VtuSample, CellBlockWithANodeOutsideThePointsIsRefused) {
  spall::discretization::CellBlock tetrahedra{spall::discretization::CellShape::tetrahedron, {0, 1, 2, 9}, {}};
  const std::vector<Vec3> points(4, Vec3::Zero());
  EXPECT_THROW(write_vtu(fs::path(::testing::TempDir()) / "bad.vtu", points, {}, {tetrahedra}), std::invalid_argument);
}

}  // namespace
