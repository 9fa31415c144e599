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
// children is 1. The push then gives c its own irradiance plus k_c times P's, so
// energy is conserved exactly, and an ancestor's irradiance reaches a leaf through the
// product of the weights along the path. Children of clusters and of elements without
// links get 1. The weights are recomputed after each refinement stage.
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
