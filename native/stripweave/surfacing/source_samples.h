// sample_source: the source the fit approximates, densely sampled with area
// weights (the source side of fit_deviation.h).
//
// Input   the Surface (its source B-rep, else its full-resolution source
//         mesh, else its own mesh in model units), the largest sample
//         spacing and the largest chordal error (model units).
// Output  SourceSamples (model units):
//           B-rep   BrepSource::dense_samples: a fine mesh with vertices
//                   exactly on the faces (and their (u, v) and face), and
//                   exact samples `spacing` apart;
//           mesh    the source mesh itself (it is the source: exact), each
//                   triangle subdivided n x n (n = longest edge / spacing)
//                   with one sample at each sub-triangle's centroid;
//         each sample weighted by its (sub-)triangle's area.
#pragma once

#include "stripweave/occt/brep_source.h"
#include "stripweave/surface/surface.h"

namespace stripweave {

// For a mesh source `uv` and `face` are empty and `points` need not be one
// per mesh triangle.
using SourceSamples = BrepDenseSamples;

SourceSamples sample_source(const Surface& surface, double spacing, double chord);

}  // namespace stripweave
