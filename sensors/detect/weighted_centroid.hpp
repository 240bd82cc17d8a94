/// @file weighted_centroid.hpp
/// Shared core of the "cog" and "iwc" centroiders: the weighted centre of the background-
/// subtracted pixels s_i with weights g_i (1 for CoG, a Gaussian around the estimate for the
/// IWC), and its covariance by linearising the fixed-point equation
///   F(x) = sum_i g_i(x) s_i (p_i - x) = 0
///   cov = J^-1 (sum_i var_i g_i^2 d_i d_i^T) J^-T,  J = dF/dx = sum_i s_i g_i (d_i d_i^T/w^2 - I)
/// with d_i = p_i - x and var_i from the patch's noise model (for CoG: J = -flux * I).
#pragma once
#include "sensors/detect/centroider.hpp"

namespace st::detail {

/// `weight_sigma` <= 0: flat weights (CoG, one pass). Otherwise iterate the Gaussian-weighted
/// centre from `start` until it moves less than 1e-4 px (at most `max_iter` times).
bool weightedCentroid(const StarPatch& patch, const Vec2& start, double weight_sigma,
                      int max_iter, Centroid& out, std::string* reason);

}  // namespace st::detail
