#pragma once
// How the contact filters' scales follow the fingertip pad that will touch
// the contacts (docs/preprocess.md#5-contact-filters).

#include "hfts_db/object_database.h"

namespace hfts::preprocess {

/// Patch radius over pad radius. PCL's surface variation is scale-free on a
/// sharp edge (about 0.08 at 90 degrees, whatever the radius) but grows as
/// (radius / R)^2 on a surface of radius of curvature R, so max_curvature
/// 0.03 over a patch of radius r keeps surfaces with R above about 1.2 r
/// and removes about 0.7 r beside a sharp edge. r = pad / 2 makes a surface
/// smooth for a pad when R >= 0.6 pad: where a pad's contact patch (about
/// half its radius across, pressed in by an eighth of its radius) stays on
/// one nearly flat piece of surface.
inline constexpr double kPatchPerPad = 0.5;

/// The share of a flat patch's samples that must lie around a contact for
/// it to stand on a surface, not on an island or a sliver.
inline constexpr double kNeighbourShare = 1.0 / 3.0;

/// `params` with the filter scales left 0 filled in from params.pad_radius:
/// patch_radius = kPatchPerPad x pad_radius, min_neighbours =
/// kNeighbourShare x the samples a disc of radius patch_radius holds at
/// `samplesPerSquareMetre`, rounded, at least 1. Scales given (non-zero)
/// are kept. (The concavity filter's depth is not the pad's: how deep a
/// finger reaches into a pocket depends on the finger and the pocket's
/// opening, which the clearance filter checks with the pad itself.)
/// Throws InvalidArgument unless pad_radius and samplesPerSquareMetre are
/// positive and finite.
db::BuildParameters resolveFilterScales(db::BuildParameters params, double samplesPerSquareMetre);

}  // namespace hfts::preprocess
