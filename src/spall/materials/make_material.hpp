#pragma once
// The constitutive library's Material for one part of a model: its *MAT_ card and, where it has
// one, its *EOS_ card.
#include "spall/materials/material.hpp"
#include "spall/model/model.hpp"

namespace spall::materials {

// Throws InputError at the line of the card at fault for what cannot run: a *MAT_RIGID part, an
// EOSID on a material that computes its own pressure, a *MAT_NULL or a *MAT_JOHNSON_COOK with
// E = 0 without EOS, a missing material, EOS or LCSS curve.
Material make_material(const model::Model& model, const model::Part& part);

}  // namespace spall::materials
