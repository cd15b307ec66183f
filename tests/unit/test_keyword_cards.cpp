// Every supported card read from small decks: values, documented defaults, layouts and syntax.
#include <gtest/gtest.h>

#include <numbers>

#include "keyword_test_decks.hpp"
#include "spall/io/keyword/reader.hpp"

namespace spall::io::keyword {
namespace {

using test::DeckFolder;
using test::row;

const std::initializer_list<int> node_widths = {8, 16, 16, 16, 8, 8};
const std::initializer_list<int> i8 = {8, 8, 8, 8, 8, 8, 8, 8, 8, 8};

std::string cube_nodes() {
  std::string text = "*NODE\n";
  int nid = 1;
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x)
        text += row({std::to_string(nid++), std::to_string(x), std::to_string(y), std::to_string(z)},
                    node_widths);
  return text;
}

// A deck with every supported card and the optional fields left blank.
TEST(keyword_cards, EveryCardWithItsDefaults) {
  DeckFolder folder;
  const std::string deck =
      "*KEYWORD\n*TITLE\nall cards with defaults\n" + cube_nodes() +
      "*PART\nblock\n" + row({"1", "1", "1"}) +
      "*PART\nrigid tool\n" + row({"2", "1", "2"}) +
      "*PART\nwater\n" + row({"3", "2", "1"}) +
      "*SECTION_SOLID\n" + row({"1"}) +
      "*SECTION_SPH\n" + row({"2"}) +
      "*MAT_ELASTIC\n" + row({"1", "7.85e-9", "2.0e5"}) +
      "*MAT_RIGID\n" + row({"2", "7.85e-9", "2.0e5", "0.3"}) + "\n" +
      "*ELEMENT_SOLID\n" + row({"1", "1", "1", "2", "4", "3", "5", "6", "8", "7"}, i8) +
      "*ELEMENT_SPH\n" + row({"8", "3", "1.0e-3"}, {8, 8, 16}) +
      "*SET_NODE_LIST\n" + row({"1"}) + row({"1", "2", "3"}) +
      "*SET_PART_LIST\n" + row({"1"}) + row({"1", "2"}) +
      "*DEFINE_CURVE\n" + row({"1"}) + row({"0.0", "0.0"}, {20, 20}) +
      row({"1.0", "1.0"}, {20, 20}) +
      "*BOUNDARY_SPC_NODE\n" + row({"1", "0", "1", "0", "1"}) +
      "*BOUNDARY_SPC_SET\n" + row({"1", "", "1", "1", "1", "1", "1", "1"}) +
      "*BOUNDARY_PRESCRIBED_MOTION_NODE\n" + row({"5", "3", "2", "1"}) +
      "*BOUNDARY_PRESCRIBED_MOTION_SET\n" + row({"1", "1", "", "1"}) +
      "*BOUNDARY_PRESCRIBED_MOTION_RIGID\n" + row({"2", "7", "0", "1"}) +
      "*INITIAL_VELOCITY\n" + row({}) + row({"1.0", "2.0", "3.0"}) +
      "*INITIAL_VELOCITY_NODE\n" + row({"2", "5.0", "6.0", "7.0"}) +
      "*INITIAL_VELOCITY_GENERATION\n" + row({"1", "2", "", "100.0"}) + row({}) +
      "*LOAD_BODY_Z\n" + row({"1"}) +
      "*CONTROL_TERMINATION\n" + row({"1.0"}) +
      "*CONTROL_TIMESTEP\n" + row({}) +
      "*CONTROL_BULK_VISCOSITY\n" + row({"0", "0", "0"}) +
      "*DATABASE_BINARY_D3PLOT\n" + row({"1.0e-3"}) +
      "*DATABASE_GLSTAT\n" + row({"1.0e-4"}) + "*END\n";
  const model::Model model = read_deck(folder.write("all.k", deck));
  EXPECT_NO_THROW(validate(model));
  EXPECT_EQ(model.title, "all cards with defaults");
  EXPECT_TRUE(model.unsupported.empty());

  ASSERT_EQ(model.nodes.size(), 8u);
  EXPECT_EQ(model.nodes[6].id, 7);
  EXPECT_EQ(model.nodes[6].x, Vec3(0, 1, 1));
  EXPECT_EQ(model.nodes[6].tc, 0);
  EXPECT_EQ(model.nodes[6].rc, 0);
  EXPECT_EQ(model.nodes[6].where.line, 11);

  ASSERT_EQ(model.parts.size(), 3u);
  EXPECT_EQ(model.parts[1].heading, "rigid tool");
  EXPECT_EQ(model.parts[1].mid, 2);
  EXPECT_EQ(model.parts[1].eosid, 0);
  EXPECT_EQ(model.parts[1].hgid, 0);

  const auto& solid = std::get<model::SectionSolid>(model.sections.at(1));
  EXPECT_EQ(solid.elform, 1);
  EXPECT_EQ(solid.aet, 0);
  const auto& sph = std::get<model::SectionSph>(model.sections.at(2));
  EXPECT_EQ(sph.cslh, 1.2);
  EXPECT_EQ(sph.hmin, 0.2);
  EXPECT_EQ(sph.hmax, 2.0);
  EXPECT_EQ(sph.sphini, 0.0);
  EXPECT_EQ(sph.death, 1.0e20);
  EXPECT_EQ(sph.start, 0.0);
  EXPECT_EQ(sph.sphkern, 0);

  const auto& elastic = std::get<model::MatElastic>(model.materials.at(1).params);
  EXPECT_EQ(elastic.ro, 7.85e-9);
  EXPECT_EQ(elastic.e, 2.0e5);
  EXPECT_EQ(elastic.pr, 0.0);
  EXPECT_EQ(elastic.da, 0.0);
  EXPECT_EQ(elastic.db, 0.0);
  EXPECT_EQ(model.materials.at(1).keyword, "*MAT_ELASTIC");
  const auto& rigid = std::get<model::MatRigid>(model.materials.at(2).params);
  EXPECT_EQ(rigid.pr, 0.3);
  EXPECT_EQ(rigid.cmo, 0.0);
  EXPECT_EQ(rigid.con1, 0);
  EXPECT_EQ(rigid.con2, 0);

  ASSERT_EQ(model.solid_elements.size(), 1u);
  EXPECT_EQ(model.solid_elements[0].n, (std::array<Id, 8>{1, 2, 4, 3, 5, 6, 8, 7}));
  ASSERT_EQ(model.sph_elements.size(), 1u);
  EXPECT_EQ(model.sph_elements[0].mass, 1.0e-3);

  EXPECT_EQ(model.node_sets.at(1).nodes, (std::vector<Id>{1, 2, 3}));
  EXPECT_EQ(model.part_sets.at(1).parts, (std::vector<Id>{1, 2}));

  const auto& curve = model.curves.at(1);
  EXPECT_EQ(curve.sidr, 0);
  EXPECT_EQ(curve.sfa, 1.0);
  EXPECT_EQ(curve.sfo, 1.0);
  EXPECT_EQ(curve.offa, 0.0);
  EXPECT_EQ(curve.offo, 0.0);
  EXPECT_EQ(curve.points.size(), 2u);

  ASSERT_EQ(model.spcs.size(), 2u);
  EXPECT_EQ(model.spcs[0].target, model::Target::node);
  EXPECT_EQ(model.spcs[0].dof, (std::array<bool, 6>{true, false, true, false, false, false}));
  EXPECT_EQ(model.spcs[1].target, model::Target::node_set);
  EXPECT_EQ(model.spcs[1].cid, 0);
  EXPECT_EQ(model.spcs[1].dof, (std::array<bool, 6>{true, true, true, true, true, true}));

  ASSERT_EQ(model.prescribed_motions.size(), 3u);
  const auto& motion = model.prescribed_motions[0];
  EXPECT_EQ(motion.target, model::Target::node);
  EXPECT_EQ(motion.dof, 3);
  EXPECT_EQ(motion.vad, 2);
  EXPECT_EQ(motion.sf, 1.0);
  EXPECT_EQ(motion.vid, 0);
  EXPECT_EQ(motion.death, 1.0e28);
  EXPECT_EQ(motion.birth, 0.0);
  EXPECT_EQ(model.prescribed_motions[1].target, model::Target::node_set);
  EXPECT_EQ(model.prescribed_motions[1].vad, 0);
  EXPECT_EQ(model.prescribed_motions[2].target, model::Target::part);
  EXPECT_EQ(model.prescribed_motions[2].id, 2);

  ASSERT_EQ(model.initial_velocities.size(), 1u);
  EXPECT_EQ(model.initial_velocities[0].nsid, 0);  // all nodes
  EXPECT_EQ(model.initial_velocities[0].v, Vec3(1, 2, 3));
  EXPECT_EQ(model.initial_velocities[0].vr, Vec3::Zero());
  ASSERT_EQ(model.initial_velocity_nodes.size(), 1u);
  EXPECT_EQ(model.initial_velocity_nodes[0].v, Vec3(5, 6, 7));
  ASSERT_EQ(model.initial_velocity_generations.size(), 1u);
  const auto& generation = model.initial_velocity_generations[0];
  EXPECT_EQ(generation.styp, 2);
  EXPECT_EQ(generation.omega, 0.0);
  EXPECT_EQ(generation.v, Vec3(100, 0, 0));
  EXPECT_EQ(generation.xc, Vec3::Zero());

  ASSERT_EQ(model.body_loads.size(), 1u);
  EXPECT_EQ(model.body_loads[0].direction, 2);
  EXPECT_EQ(model.body_loads[0].sf, 1.0);
  EXPECT_EQ(model.body_loads[0].lciddr, 0);

  ASSERT_TRUE(model.termination);
  EXPECT_EQ(model.termination->endtim, 1.0);
  EXPECT_EQ(model.termination->endcyc, 0);
  EXPECT_EQ(model.termination->dtmin, 0.0);
  EXPECT_EQ(model.termination->endeng, 0.0);
  EXPECT_EQ(model.termination->endmas, 1.0e8);
  EXPECT_EQ(model.timestep.tssfac, 0.9);
  EXPECT_EQ(model.timestep.dtinit, 0.0);
  EXPECT_EQ(model.timestep.lctm, 0);
  EXPECT_EQ(model.bulk_viscosity.q1, 1.5);
  EXPECT_EQ(model.bulk_viscosity.q2, 0.06);
  EXPECT_EQ(model.bulk_viscosity.type, 1);
  ASSERT_TRUE(model.d3plot);
  EXPECT_EQ(model.d3plot->dt, 1.0e-3);
  EXPECT_EQ(model.d3plot->lcdt, 0);
  EXPECT_EQ(model.d3plot->beam, 0);
  EXPECT_EQ(model.d3plot->npltc, 0);
  ASSERT_TRUE(model.glstat);
  EXPECT_EQ(model.glstat->dt, 1.0e-4);
}

TEST(keyword_cards, ValuesGivenOverrideDefaults) {
  DeckFolder folder;
  const std::string deck =
      "*KEYWORD\n*SECTION_SPH_TITLE\nbird\n" +
      row({"4", "1.1", "0.5", "1.5", "0.2", "2.0", "0.1", "1"}) +
      "*MAT_020_TITLE\ntool\n" + row({"2", "7.8e-9", "2.0e5", "0.3"}) + row({"1", "4", "7"}) +
      row({"0"}) +
      "*MAT_001\n" + row({"5", "1.0e-9", "1.0e3", "0.45", "0.1", "0.2"}) +
      "*CONTROL_TIMESTEP\n" + row({"1.0e-7", "0.6", "0", "0.0", "-1.0e-6", "3"}) +
      "*CONTROL_BULK_VISCOSITY\n" + row({"2.0", "0.1", "-2"}) +
      "*CONTROL_TERMINATION\n" + row({"2.0", "100", "0.01", "0.5", "5.0"}) +
      "*LOAD_BODY_Y\n" + row({"3", "-9.81", "4", "1.0", "2.0", "3.0", "0"}) +
      "*DATABASE_BINARY_D3PLOT\n" + row({"0", "5", "1", "20"}) + "*END\n";
  const model::Model model = read_deck(folder.write("given.k", deck));
  const auto& sph = std::get<model::SectionSph>(model.sections.at(4));
  EXPECT_EQ(sph.cslh, 1.1);
  EXPECT_EQ(sph.hmin, 0.5);
  EXPECT_EQ(sph.hmax, 1.5);
  EXPECT_EQ(sph.sphini, 0.2);
  EXPECT_EQ(sph.death, 2.0);
  EXPECT_EQ(sph.start, 0.1);
  EXPECT_EQ(sph.sphkern, 1);
  const auto& rigid = std::get<model::MatRigid>(model.materials.at(2).params);
  EXPECT_EQ(model.materials.at(2).keyword, "*MAT_RIGID");
  EXPECT_EQ(rigid.cmo, 1.0);
  EXPECT_EQ(rigid.con1, 4);
  EXPECT_EQ(rigid.con2, 7);
  EXPECT_EQ(std::get<model::MatElastic>(model.materials.at(5).params).db, 0.2);
  EXPECT_EQ(model.timestep.tssfac, 0.6);
  EXPECT_EQ(model.timestep.dt2ms, -1.0e-6);
  EXPECT_EQ(model.timestep.lctm, 3);
  EXPECT_EQ(model.bulk_viscosity.q1, 2.0);
  EXPECT_EQ(model.bulk_viscosity.q2, 0.1);
  EXPECT_EQ(model.bulk_viscosity.type, -2);
  EXPECT_EQ(model.termination->endcyc, 100);
  EXPECT_EQ(model.termination->endmas, 5.0);
  EXPECT_EQ(model.body_loads[0].direction, 1);
  EXPECT_EQ(model.body_loads[0].sf, -9.81);
  EXPECT_EQ(model.body_loads[0].lciddr, 4);
  EXPECT_EQ(model.body_loads[0].xc, Vec3(1, 2, 3));
  EXPECT_EQ(model.d3plot->lcdt, 5);
  EXPECT_EQ(model.d3plot->beam, 1);
  EXPECT_EQ(model.d3plot->npltc, 20);
}

TEST(keyword_cards, BothElementSolidLayoutsGiveTheSameElement) {
  DeckFolder folder;
  const std::string legacy = "*KEYWORD\n*ELEMENT_SOLID\n" +
                             row({"7", "1", "1", "2", "4", "3", "5", "6", "8", "7"}, i8) +
                             row({"8", "1", "1", "2", "3", "4", "4", "4", "4", "4"}, i8);
  // LS-PrePost's ten-node format, with its trailing text on the keyword line.
  const std::string ten_nodes = "*KEYWORD\n*ELEMENT_SOLID (ten nodes format)\n$#   eid     pid\n" +
                                row({"7", "1"}, i8) +
                                row({"1", "2", "4", "3", "5", "6", "8", "7", "0", "0"}, i8) +
                                row({"8", "1"}, i8) +
                                row({"1", "2", "3", "4", "4", "4", "4", "4"}, i8);
  const auto a = read_deck(folder.write("legacy.k", legacy));
  const auto b = read_deck(folder.write("ten.k", ten_nodes));
  ASSERT_EQ(a.solid_elements.size(), 2u);
  ASSERT_EQ(b.solid_elements.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(a.solid_elements[k].eid, b.solid_elements[k].eid);
    EXPECT_EQ(a.solid_elements[k].pid, b.solid_elements[k].pid);
    EXPECT_EQ(a.solid_elements[k].n, b.solid_elements[k].n);
  }
  EXPECT_EQ(b.solid_elements[1].n, (std::array<Id, 8>{1, 2, 3, 4, 4, 4, 4, 4}));
  EXPECT_EQ(b.solid_elements[0].where.line, 4);
}

TEST(keyword_cards, SphNendGeneratesParticlesAndNegativeMassIsVolume) {
  DeckFolder folder;
  const std::string deck = "*KEYWORD\n*ELEMENT_SPH\n" + row({"10", "3", "-15625", "14"}, {8, 8, 16, 8}) +
                           row({"20", "3", "2.5e-3"}, {8, 8, 16}) +
                           "*ELEMENT_SPH_VOLUME\n" + row({"30", "4", "8.0"}, {8, 8, 16}) + "*END\n";
  const auto model = read_deck(folder.write("sph.k", deck));
  ASSERT_EQ(model.sph_elements.size(), 7u);
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(model.sph_elements[k].nid, 10 + k);
    EXPECT_EQ(model.sph_elements[k].pid, 3);
    EXPECT_EQ(model.sph_elements[k].mass, -15625.0);
  }
  EXPECT_EQ(model.sph_elements[5].nid, 20);
  EXPECT_EQ(model.sph_elements[5].mass, 2.5e-3);
  EXPECT_EQ(model.sph_elements[6].mass, -8.0);  // _VOLUME: stored as LS-DYNA's negative volume
}

// A generated range is expanded once the deck is read, and holds no more IDs than the deck has nodes
// (the cube's 8 here).
TEST(keyword_cards, NodeSetsListAndGenerate) {
  DeckFolder folder;
  const std::string deck = "*KEYWORD\n*SET_NODE_LIST_TITLE\nclamped edge\n" + row({"3"}) +
                           row({"5", "6", "0", "", "9"}) + row({"11"}) +
                           "*SET_NODE_LIST_GENERATE\n" + row({"4"}) + row({"1", "3", "10", "12"}) +
                           row({"20", "20"}) + "*SET_PART_LIST_TITLE\nall\n" + row({"2"}) +
                           row({"1", "2", "3"}) + cube_nodes() + "*END\n";
  const auto model = read_deck(folder.write("sets.k", deck));
  EXPECT_EQ(model.node_sets.at(3).nodes, (std::vector<Id>{5, 6, 9, 11}));
  EXPECT_EQ(model.node_sets.at(4).nodes, (std::vector<Id>{1, 2, 3, 10, 11, 12, 20}));
  EXPECT_EQ(model.part_sets.at(2).parts, (std::vector<Id>{1, 2, 3}));
}

TEST(keyword_cards, CurveScalingAndOffsets) {
  DeckFolder folder;
  const std::string deck = "*KEYWORD\n*DEFINE_CURVE_TITLE\nramp\n" +
                           row({"7", "0", "2.0", "3.0", "1.0", "0.5"}) +
                           row({"0.0", "0.0"}, {20, 20}) + row({"1.0", "10.0"}, {20, 20}) +
                           "*DEFINE_CURVE\n" + row({"8", "", "0.0", "0"}) +
                           row({"0.0", "1.0"}, {20, 20}) + "*END\n";
  const auto model = read_deck(folder.write("curve.k", deck));
  const auto& curve = model.curves.at(7);
  EXPECT_EQ(curve.sfa, 2.0);
  EXPECT_EQ(curve.sfo, 3.0);
  EXPECT_EQ(curve.offa, 1.0);
  EXPECT_EQ(curve.offo, 0.5);
  // value(t) = SFO f((t - OFFA) / SFA) + OFFO: at t = 2, f(0.5) = 5.
  EXPECT_DOUBLE_EQ(curve.value(2.0), 3.0 * 5.0 + 0.5);
  EXPECT_EQ(model.curves.at(8).sfa, 1.0);  // 0 means 1.0
  EXPECT_EQ(model.curves.at(8).sfo, 1.0);
}

TEST(keyword_cards, IncludeIsRelativeToTheIncludingFile) {
  DeckFolder folder;
  folder.write("sub/nodes.k", "*KEYWORD\n*INCLUDE\nmore/deeper.k\n*NODE\n" +
                                  row({"1", "0", "0", "0"}, node_widths) + "*END\n");
  folder.write("sub/more/deeper.k", "*NODE\n" + row({"2", "1", "0", "0"}, node_widths));
  const auto path = folder.write("main.k", "*KEYWORD\n*INCLUDE\nsub/nodes.k\n*NODE\n" +
                                               row({"3", "2", "0", "0"}, node_widths) + "*END\n");
  const auto model = read_deck(path);
  ASSERT_EQ(model.nodes.size(), 3u);
  EXPECT_EQ(model.nodes[0].id, 2);  // read in include order
  EXPECT_EQ(model.nodes[1].id, 1);
  EXPECT_EQ(model.nodes[2].id, 3);
  EXPECT_EQ(model.files.size(), 3u);
  EXPECT_NE(model.nodes[0].where.file.str().find("deeper.k"), std::string::npos);
  EXPECT_EQ(model.nodes[0].where.line, 2);
}

// Every node and element remembers where it was read; the file's name is held once, not copied
// into each (a million-particle deck read from a long path held 150 MB of copies).
TEST(keyword_cards, ItemsOfOneFileShareItsName) {
  // The name's number and the line: a node's card 48 B, a particle's 32 B.
  static_assert(sizeof(SourceLocation) <= 8);
  static_assert(sizeof(model::Node) <= 48 && sizeof(model::ElementSph) <= 32);
  DeckFolder folder;
  const auto path = folder.write("a_folder_name_longer_than_a_short_string/deck.k",
                                 "*KEYWORD\n*NODE\n" + row({"1", "0", "0", "0"}, node_widths) +
                                     row({"2", "1", "0", "0"}, node_widths) + "*END\n");
  const auto model = read_deck(path);
  ASSERT_EQ(model.nodes.size(), 2u);
  const std::string& name = model.nodes[0].where.file.str();
  EXPECT_NE(name.find("a_folder_name_longer_than_a_short_string/deck.k"), std::string::npos);
  EXPECT_EQ(&model.nodes[1].where.file.str(), &name);
  EXPECT_EQ(&FileName(std::string(name)).str(), &name);  // the same text is the same name
  EXPECT_NE(&FileName("another.k").str(), &name);
  EXPECT_TRUE(FileName().empty());
  EXPECT_TRUE(FileName("").empty());
}

TEST(keyword_cards, CommentsCaseEndAndFreeFormat) {
  DeckFolder folder;
  const std::string deck =
      "$ a comment before *KEYWORD\n*keyword\n*Node\n$#   nid               x\n" +
      row({"1", "1.0+1", "2.5D-1", "0"}, node_widths) + "$ a comment between cards\n" +
      "2, 3.0, 4.0, 5.0\n" + "   \n" + "*END\n*NODE\nthis is not read: 1.2.3\n";
  const auto model = read_deck(folder.write("syntax.k", deck));
  ASSERT_EQ(model.nodes.size(), 2u);
  EXPECT_EQ(model.nodes[0].x, Vec3(10.0, 0.25, 0.0));
  EXPECT_EQ(model.nodes[1].x, Vec3(3.0, 4.0, 5.0));
  EXPECT_EQ(model.nodes[1].where.line, 7);
}

TEST(keyword_cards, LongFormatByKeywordOptionAndSuffix) {
  DeckFolder folder;
  const std::initializer_list<int> wide = {20, 20, 20, 20, 20, 20};
  const std::string deck = "*KEYWORD LONG=Y\n*NODE\n" + row({"123456789012", "1.5", "2.5", "3.5"}, wide) +
                           "*NODE-\n" + row({"2", "1", "2", "3"}, node_widths) + "*END\n";
  const auto model = read_deck(folder.write("long.k", deck));
  ASSERT_EQ(model.nodes.size(), 2u);
  EXPECT_EQ(model.nodes[0].id, 123456789012);
  EXPECT_EQ(model.nodes[0].x, Vec3(1.5, 2.5, 3.5));
  EXPECT_EQ(model.nodes[1].x, Vec3(1, 2, 3));

  const std::string plus = "*KEYWORD\n*SECTION_SOLID+\n" + row({"5", "2"}, {20, 20}) +
                           "*SECTION_SOLID\n" + row({"6", "2"}) + "*END\n";
  const auto model2 = read_deck(folder.write("plus.k", plus));
  EXPECT_EQ(std::get<model::SectionSolid>(model2.sections.at(5)).elform, 2);
  EXPECT_EQ(std::get<model::SectionSolid>(model2.sections.at(6)).elform, 2);
}

TEST(keyword_cards, IdOptionOfBoundaryConditions) {
  DeckFolder folder;
  const std::string deck = "*KEYWORD\n*BOUNDARY_SPC_SET_ID\n" + row({"1", "base"}) +
                           row({"9", "0", "1", "1", "1"}) +
                           "*BOUNDARY_PRESCRIBED_MOTION_RIGID_ID\n" + row({"2", "spin"}) +
                           row({"4", "7", "0", "3", "6.28"}) + "*END\n";
  const auto model = read_deck(folder.write("id.k", deck));
  ASSERT_EQ(model.spcs.size(), 1u);
  EXPECT_EQ(model.spcs[0].id, 9);
  EXPECT_EQ(model.spcs[0].target, model::Target::node_set);
  ASSERT_EQ(model.prescribed_motions.size(), 1u);
  EXPECT_EQ(model.prescribed_motions[0].id, 4);
  EXPECT_EQ(model.prescribed_motions[0].sf, 6.28);
}

TEST(keyword_cards, ParameterExpressions) {
  DeckFolder folder;
  const std::string deck =
      "*KEYWORD\n*PARAMETER\n" + row({"R a", "2.0", "I n", "3"}) +
      "*PARAMETER_EXPRESSION\n"
      "R b       (a + 1)**2 * sqrt(4.0) - max(n, 1)/3\n"
      "I id      n*10 + abs(-2)\n"
      "R c       -a**2 + cos(0) + exp(log(2.0)) + min(a,n)\n" +
      "*SECTION_SOLID\n" + row({"&id", "1"}) +
      "*SECTION_SPH\n" + row({"1", "&b", "", "&c", "-&a"}) + "*END\n";
  const auto model = read_deck(folder.write("expr.k", deck));
  ASSERT_TRUE(model.sections.contains(32));
  const auto& sph = std::get<model::SectionSph>(model.sections.at(1));
  EXPECT_DOUBLE_EQ(sph.cslh, 9.0 * 2.0 - 1.0);
  EXPECT_DOUBLE_EQ(sph.hmax, -4.0 + 1.0 + 2.0 + 2.0);
  EXPECT_DOUBLE_EQ(sph.sphini, -2.0);
}

// The manual's constant pi and its Fortran functions; a long expression continues on lines whose
// PRMR columns are blank.
TEST(keyword_cards, ParameterExpressionFunctionsPiAndContinuation) {
  DeckFolder folder;
  const std::string deck =
      "*KEYWORD\n*PARAMETER_EXPRESSION\n"
      "R angle   pi/4\n"
      "R trig    sin(angle)**2 + cos(angle)**2 + tan(angle) + atan2(1.0, 1.0)*4/pi\n"
      "R ints    aint(-2.7) + anint(2.5) + int(3.9) + nint(-2.5) + float(1)\n"
      "R more    max(1, 7, 3) - min(4, -2, 0) + sign(3, -1) + mod(7, 3) + log10(100.0)\n"
      "R long    1 + 2\n"
      "          + 3\n"
      "          * 4\n"
      "*SECTION_SPH\n" + row({"1", "&trig", "&ints", "&more"}) +
      "*SECTION_SPH\n" + row({"2", "&long", "", "", "", "", "&angle"}) + "*END\n";
  const auto model = read_deck(folder.write("expr.k", deck));
  const auto& sph = std::get<model::SectionSph>(model.sections.at(1));
  EXPECT_DOUBLE_EQ(sph.cslh, 1.0 + 1.0 + 1.0);
  EXPECT_DOUBLE_EQ(sph.hmin, -2.0 + 3.0 + 3.0 - 3.0 + 1.0);
  EXPECT_DOUBLE_EQ(sph.hmax, 7.0 + 2.0 - 3.0 + 1.0 + 2.0);
  const auto& continued = std::get<model::SectionSph>(model.sections.at(2));
  EXPECT_DOUBLE_EQ(continued.cslh, 1.0 + 2.0 + 3.0 * 4.0);
  EXPECT_DOUBLE_EQ(continued.start, std::numbers::pi / 4);
}

// *COMMENT is free text up to the next keyword: neither read nor reported as unsupported.
TEST(keyword_cards, CommentBlocksAreSkippedSilently) {
  DeckFolder folder;
  const std::string deck = "*KEYWORD\n*COMMENT\nWritten by LS-PrePost, 1,2,3\n  any text at all\n" +
                           std::string("*SECTION_SOLID\n") + row({"4", "1"}) + "*END\n";
  const auto model = read_deck(folder.write("comment.k", deck));
  EXPECT_TRUE(model.unsupported.empty());
  EXPECT_TRUE(model.sections.contains(4));
}

// *SECTION_SHELL (T2-T4 take T1; ICOMP 1's layer angles, eight a line, are passed over) and
// *ELEMENT_SHELL (a triangle repeats N3; _THICKNESS adds THIC1-THIC4), on a rigid part.
TEST(keyword_cards, RigidShellSectionsAndElements) {
  DeckFolder folder;
  const std::string deck =
      "*KEYWORD\n*CONTROL_TERMINATION\n" + row({"1.0"}) + "*NODE\n" + row({"1", "0", "0", "0"}, {8, 16, 16, 16}) +
      row({"2", "1", "0", "0"}, {8, 16, 16, 16}) + row({"3", "1", "1", "0"}, {8, 16, 16, 16}) +
      row({"4", "0", "1", "0"}, {8, 16, 16, 16}) + "*PART\ntool\n" + row({"1", "7", "1"}) +
      "*SECTION_SHELL_TITLE\nskin\n" + row({"7", "16", "", "9", "", "", "1"}) +
      row({"0.5", "", "0.7", "", "", "0.25"}) + row({"0", "45", "90", "0", "45", "90", "0", "45"}) + row({"90"}) +
      "*MAT_RIGID\n" + row({"1", "7.8e-9", "2.1e5", "0.3"}) + row({}) + "*ELEMENT_SHELL\n" +
      row({"1", "1", "1", "2", "3", "4"}, {8, 8, 8, 8, 8, 8}) + row({"2", "1", "1", "2", "3"}, {8, 8, 8, 8, 8}) +
      "*ELEMENT_SHELL_THICKNESS\n" + row({"3", "1", "1", "3", "4", "4"}, {8, 8, 8, 8, 8, 8}) +
      row({"0.1", "0.2", "0.3"}, {16, 16, 16}) + "*END\n";
  const model::Model model = read_deck(folder.write("shells.k", deck));
  EXPECT_NO_THROW(validate(model));
  EXPECT_TRUE(model.unsupported.empty());
  const auto& section = std::get<model::SectionShell>(model.sections.at(7));
  EXPECT_EQ(section.elform, 16);
  EXPECT_EQ(section.t, (std::array<Real, 4>{0.5, 0.5, 0.7, 0.5}));
  EXPECT_EQ(section.marea, 0.25);
  ASSERT_EQ(model.shell_elements.size(), 3u);
  EXPECT_EQ(model.shell_elements[0].n, (std::array<Id, 4>{1, 2, 3, 4}));
  EXPECT_FALSE(model.shell_elements[0].is_triangle());
  EXPECT_TRUE(model.shell_elements[1].is_triangle());
  EXPECT_EQ(model.shell_elements[1].where.line, 23);
  EXPECT_TRUE(model.shell_elements[2].is_triangle());
  EXPECT_EQ(model.shell_thickness(model.shell_elements[2]), (std::array<Real, 4>{0.1, 0.2, 0.3, 0.5}));
  EXPECT_EQ(model.shell_thickness(model.shell_elements[0]), section.t);
}

// *PART_INERTIA: a *PART with cards 3-5, and card 6 with IRCS 1; a lone card 6 after an IRCS 0
// part is read as card 6 (some writers give it always), not as another part's heading.
TEST(keyword_cards, PartInertiaCards) {
  DeckFolder folder;
  const std::string deck = "*KEYWORD\n*PART_INERTIA\nwheel\n" + row({"4", "1", "2"}) +
                           row({"1.0", "2.0", "3.0", "5.5", "1", "0"}) +
                           row({"2.0", "0.1", "0.2", "3.0", "0.3", "4.0"}) +
                           row({"1.0", "", "", "", "", "9.0"}) + row({"0", "1", "0", "0", "0", "1"}) +
                           "hub\n" + row({"5", "1", "2"}) + row({"", "", "", "1.5", "", "7"}) + row({"1.0"}) + row({}) +
                           row({"1.0", "0", "0", "0", "1.0", "0"}) + "*END\n";
  const model::Model model = read_deck(folder.write("inertia.k", deck));
  ASSERT_EQ(model.parts.size(), 2u);
  const model::PartInertia& wheel = *model.parts[0].inertia;
  EXPECT_EQ(model.parts[0].heading, "wheel");
  EXPECT_EQ(wheel.centre, Vec3(1, 2, 3));
  EXPECT_EQ(wheel.mass, 5.5);
  EXPECT_TRUE(wheel.local);
  EXPECT_EQ(wheel.tensor(0, 1), 0.1);
  EXPECT_EQ(wheel.tensor(2, 0), 0.2);
  EXPECT_EQ(wheel.tensor(2, 1), 0.3);
  EXPECT_EQ(wheel.tensor(2, 2), 4.0);
  EXPECT_EQ(wheel.velocity, Vec3(1, 0, 0));
  EXPECT_EQ(wheel.angular_velocity, Vec3(0, 0, 9));
  EXPECT_EQ(wheel.local_x, Vec3(0, 1, 0));
  EXPECT_EQ(wheel.local_in_plane, Vec3(0, 0, 1));
  const model::PartInertia& hub = *model.parts[1].inertia;
  EXPECT_FALSE(hub.local);
  EXPECT_EQ(hub.node, 7);
  EXPECT_EQ(hub.tensor(0, 0), 1.0);
  EXPECT_EQ(model.parts[1].where.line, 10);
  EXPECT_EQ(hub.local_x, Vec3(1, 0, 0));  // read, and of no use with IRCS 0
}

TEST(keyword_cards, UnsupportedKeywordsAreRecordedWithNameLineAndId) {
  DeckFolder folder;
  const std::string deck = "*KEYWORD\n*MAT_SOIL_AND_FOAM\n" + row({"6", "1.0e-9"}) +
                           "*SECTION_BEAM_TITLE\nbar\n" + row({"3", "2"}) +
                           "*EOS_JWL\n" + row({"6", "371.2"}) +
                           "*CONTACT_TIED_NODES_TO_SURFACE_ID\n" + row({"1"}) + row({"1", "2"}) +
                           "*CONTROL_SHELL\n" + row({"1"}) +
                           "*DEFINE_TABLE_TITLE\nrates\n" + row({"7"}) + row({"1.0", "8"}, {20, 20}) +
                           "*END\n";
  const auto model = read_deck(folder.write("unsupported.k", deck));
  ASSERT_EQ(model.unsupported.size(), 6u);
  EXPECT_EQ(model.unsupported[0].keyword, "*MAT_SOIL_AND_FOAM");
  EXPECT_EQ(model.unsupported[0].id, 6);
  EXPECT_EQ(model.unsupported[0].where.line, 2);
  EXPECT_EQ(model.unsupported[1].keyword, "*SECTION_BEAM_TITLE");
  EXPECT_EQ(model.unsupported[1].id, 3);
  EXPECT_EQ(model.unsupported[1].where.line, 4);
  EXPECT_EQ(model.unsupported[2].keyword, "*EOS_JWL");
  EXPECT_EQ(model.unsupported[2].id, 6);
  EXPECT_EQ(model.unsupported[3].keyword, "*CONTACT_TIED_NODES_TO_SURFACE_ID");
  EXPECT_EQ(model.unsupported[3].id, 0);
  EXPECT_EQ(model.unsupported[3].where.line, 9);
  EXPECT_EQ(model.unsupported[4].keyword, "*CONTROL_SHELL");
  EXPECT_EQ(model.unsupported[4].where.line, 12);
  // A table keeps its ID too, for *MAT_PIECEWISE_LINEAR_PLASTICITY's LCSS to name it.
  EXPECT_EQ(model.unsupported[5].keyword, "*DEFINE_TABLE_TITLE");
  EXPECT_EQ(model.unsupported[5].id, 7);
}

}  // namespace
}  // namespace spall::io::keyword
