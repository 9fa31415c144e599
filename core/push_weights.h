// Push weights: how a surface element shares the irradiance it receives (through its
// own links and from its ancestors') among its children.
//
// A link r <- s carries the mean of the point form factor over r, and the push hands
// that mean to every part of r. Where the form factor varies over r, a part gets more
// or less than it should; across r it evens out, but not in a leaf's row sum, whose
// parts come from several levels. A leaf in the corner of a room links at its own
// level to the squares beside it on the two walls, and inherits from its ancestors
// their mean form factor to the walls' farther parts, which it sees at grazing angles
// (an ancestor's far-from-the-wall parts see them well): in the empty furnace box at
// rho 0.9 such leaves gathered up to 1.44 of their hemisphere, their neighbours 0.83,
// and the answer came out 4.7 % high (1/(1 - rho S) turns a spread of S into a
// surplus).
//
// So each surface child c of a surface element P with links gets a weight k_c, the
// share of P's irradiance it receives relative to P's mean: the form factors from c to
// P's link sources, times each link's visibility and its source's radiosity (frozen
// during refinement; the form factor alone while every source is dark), over the
// same sum with P's own form factors, scaled so that the open-area mean of k over P's
// children is 1. The push gives c its own irradiance, what P inherited from its
// ancestors as it came, and k_c times what P's own links gathered, so energy is
// conserved exactly and each link's light is shared out once, by its own geometry,
// one level below its receiver. (Weighing P's inherited irradiance by k_c as well
// over-corrected: the empty box came out 1.9 % low, since P's own links and its
// ancestors' reach its children with different profiles.) Children of clusters and
// of elements without links get 1. The weights are recomputed after each refinement
// stage.
#pragma once

#include "core/element.h"

#include <vector>

namespace hrad {

class Transport;

/// Sets push_weight of every child of every element in `elements` (all of the
/// hierarchy's elements, parents before children or not). Uses `threads` threads.
void update_push_weights(const std::vector<Element*>& elements, const Transport& transport,
                         int threads);

}  // namespace hrad
