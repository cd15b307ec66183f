// *DEFINE_SPH_MESH_BOX: a box of SPH particles on a lattice.
//
// Card 1 XMIN YMIN ZMIN XLEN YLEN ZLEN; card 2 IPID NX NY NZ (unused) IDSEG SFSP.
//
// The box is cut into NX x NY x NZ equal cells and one particle sits at the centre of each
// (cell-centred rather than on the corners): the particles' cells then tile the box exactly, so
// the mass is RO x the box volume, two boxes sharing a face put no two particles on it, and the
// outer particles sit half a spacing inside the faces - a fluid box laid against a wall box keeps
// one spacing between their first layers. Each particle's MASS is minus its cell volume (LS-DYNA's
// "negative mass is a volume"), so its mass is RO x cell volume with the RO of the part's
// material, and the section's CSLH x (m / rho)^(1/3) gives h from the cell size. With
// *CONTROL_SPH IDIM = 2 (plane strain in x-y) NZ must be 1, the particles lie at z = ZMIN + ZLEN/2
// and the volume is per unit thickness (the cell area).
//
// Node IDs: the generated nodes (one per particle) are numbered from the largest *NODE ID of the
// deck + 1 (from 1 without *NODE), box after box in the order of the deck, and in a box with x
// fastest, then y, then z: particle (i, j, k) of a box whose first ID is F has ID
// F + i + NX (j + NY k). Sets of these nodes can so be written with *SET_NODE_LIST_GENERATE.
#include <algorithm>
#include <cmath>
#include <string>

#include "spall/core/memory.hpp"
#include "spall/io/keyword/keyword_readers.hpp"

namespace spall::io::keyword {

double particles_held(const model::Model& model, double more) {
  double count = static_cast<double>(model.sph_cards) + more;
  for (const auto& box : model.sph_mesh_boxes) count += static_cast<double>(box.nx) * box.ny * box.nz;
  return count / model.cards.ranks;
}

void read_define_sph_mesh_box(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  while (true) {
    cursor.skip_blank_lines();
    if (cursor.done()) break;
    const Card box_card = cursor.next(standard_fields, "card 1 (XMIN YMIN ZMIN XLEN YLEN ZLEN)");
    model::SphMeshBox box;
    box.lower = Vec3(box_card.real(0, "XMIN", 0.0), box_card.real(1, "YMIN", 0.0),
                     box_card.real(2, "ZMIN", 0.0));
    const char* length_names[3] = {"XLEN", "YLEN", "ZLEN"};
    for (int d = 0; d < 3; ++d) {
      box.length[d] = box_card.required_real(3 + d, length_names[d]);
      if (!(box.length[d] > 0))
        box_card.fail(length_names[d], quoted(box_card.text(3 + d)) + ": the box needs a length > 0");
    }
    const Card card = cursor.next(standard_fields, "card 2 (IPID NX NY NZ - IDSEG SFSP)");
    box.ipid = card.required_integer(0, "IPID");
    const char* count_names[3] = {"NX", "NY", "NZ"};
    double total = 1;
    for (int d = 0; d < 3; ++d) {
      const std::int64_t count = card.required_integer(1 + d, count_names[d]);
      if (count < 1)
        card.fail(count_names[d], quoted(card.text(1 + d)) + ": at least one particle per direction");
      total *= static_cast<double>(count);
      // Before the count is stored: the memory the box would take, all boxes so far included.
      if (const std::string why = memory::shortfall(particles_held(model, total), particle_bytes, "particles");
          !why.empty())
        card.fail(count_names[d], "NX x NY x NZ: " + why);
      (d == 0 ? box.nx : d == 1 ? box.ny : box.nz) = static_cast<int>(count);
    }
    box.idseg = card.integer(5, "IDSEG", 0);
    if (box.idseg != 0)
      card.fail("IDSEG", "removing the particles near segment set " + std::to_string(box.idseg) +
                             " is not supported (leave IDSEG 0)");
    // SFSP scales the removal distance from IDSEG's segments; without IDSEG it has no effect.
    box.sfsp = card.real(6, "SFSP", 0.0);
    box.where = card.where();
    model.sph_mesh_boxes.push_back(box);
  }
}

void generate_sph_mesh_box_particles(model::Model& model) {
  if (model.sph_mesh_boxes.empty()) return;
  const bool plane_strain = model.control_sph && model.control_sph->idim == 2;
  Id next_id = model.largest_node_id + 1;
  for (const auto& box : model.sph_mesh_boxes) {
    if (plane_strain && box.nz != 1)
      throw InputError(box.where, "*DEFINE_SPH_MESH_BOX",
                       "NZ " + std::to_string(box.nz) +
                           ": in plane strain (*CONTROL_SPH IDIM 2) a box has one layer, NZ 1");
    const Vec3 cell(box.length.x() / box.nx, box.length.y() / box.ny, box.length.z() / box.nz);
    const Real volume = plane_strain ? cell.x() * cell.y() : cell.prod();
    const Index count = static_cast<Index>(box.nx) * box.ny * box.nz;
    model.nodes.reserve(model.nodes.size() + count / model.cards.ranks + model::CardShare::chunk);
    model.sph_elements.reserve(model.sph_elements.size() + count / model.cards.ranks + model::CardShare::chunk);
    // The box's particle p (x fastest) is node card node_cards + p and particle card sph_cards + p; a
    // rank generates the cards it holds (CardShare). The two counts so far may differ (a deck's own
    // *NODE cards without particles), so the chunks of either may start at p: past a stretch that
    // holds neither, the next p is where one of them starts a chunk.
    for (Index p = 0; p < count; ++p) {
      const bool node = model.cards.holds(model.node_cards + p), particle = model.cards.holds(model.sph_cards + p);
      if (!node && !particle) {
        p += model::CardShare::chunk - 1 - std::max((model.node_cards + p) % model::CardShare::chunk,
                                                    (model.sph_cards + p) % model::CardShare::chunk);
        continue;
      }
      const Index i = p % box.nx, j = (p / box.nx) % box.ny, k = p / (Index(box.nx) * box.ny);
      const Vec3 x = box.lower + cell.cwiseProduct(Vec3(i + 0.5, j + 0.5, k + 0.5));
      if (node) model.nodes.push_back({next_id + p, x, 0, 0, box.where});
      if (particle) model.sph_elements.push_back({next_id + p, box.ipid, -volume, box.where});
    }
    next_id += count;
    model.node_cards += count;
    model.sph_cards += count;
  }
}

}  // namespace spall::io::keyword
