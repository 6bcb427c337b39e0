// Parameters of the elastica graph and loop search (paper §5, §8).
// Lengths are in normalized units (bounding-box diagonal 1), so the paper's
// alpha = 1 and beta = 0.25 serve every model.
#pragma once

namespace stripweave {

enum class BoundaryMode {
  Aligned,  // dual curves meet open boundaries orthogonally (boundary treated as a feature, §5.7)
  Trimmed,  // any angle is allowed: patches may be trimmed by the boundary
};

struct ElasticaParams {
  int k = 4;                  // g joins vertices at graph distance <= k (§5.3)
  double max_turn_deg = 30;   // g' joins consecutive g-edges turning by at most this (§5.3)
  double alpha = 1.0;         // weight of principal-direction alignment q (eq. 2)
  double beta = 0.25;         // weight of geodesic curvature gamma^2 / min(|e0|,|e1|) (eq. 2)
  BoundaryMode boundary = BoundaryMode::Aligned;
  // On sharp features (and aligned boundaries) the deviation term is
  // 1/|<t, c>| - 1 with c the direction across the curve (§5.6). The paper
  // weights it by the shape anisotropy, which the exact B-rep curvature does
  // not see on a crease (each side may be flat); this is the anisotropy used
  // there instead, in 1/normalized length squared (10^2: a crease acts like
  // a bend of radius 0.1 of the model).
  double feature_weight = 100.0;
};

}  // namespace stripweave
