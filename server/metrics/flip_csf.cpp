#include "metrics/flip_csf.h"

#include <array>
#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

namespace ddgi::metrics {

namespace {

constexpr double kPi = std::numbers::pi;

// The paper's CSFs as sums of two Gaussians in the spatial domain:
// S(r) = a1 sqrt(pi/b1) exp(-pi^2 r^2/b1) + a2 sqrt(pi/b2) exp(-pi^2 r^2/b2), r in degrees.
// Each Gaussian has standard deviation sqrt(b / (2 pi^2)) degrees.
struct Csf {
  double a1, b1, a2, b2;
};
constexpr std::array<Csf, 3> kCsf = {{
    {1.0, 0.0047, 0.0, 1e-5},   // achromatic (Y)
    {1.0, 0.0053, 0.0, 1e-5},   // red-green (Cx)
    {34.1, 0.04, 13.5, 0.025},  // blue-yellow (Cz)
}};
constexpr double kWidestB = 0.04;

// One Gaussian term of a CSF, sampled at whole-pixel offsets converted to degrees.
struct CsfTerm {
  Kernel1D kernel;  // normalised to sum 1
  double weight;    // this term's share of the normalised 2-D kernel
};

std::vector<CsfTerm> csf_terms(const Csf& csf, double ppd) {
  const int radius = csf_radius(ppd);
  std::vector<CsfTerm> terms;
  double total = 0.0;
  for (auto [a, b] : {std::pair{csf.a1, csf.b1}, std::pair{csf.a2, csf.b2}}) {
    if (a == 0.0) continue;
    CsfTerm term;
    term.kernel.taps.resize(size_t(2 * radius + 1));
    double sum = 0.0;
    for (int k = -radius; k <= radius; ++k) {
      const double degrees = k / ppd;
      const double tap = std::exp(-kPi * kPi * degrees * degrees / b);
      term.kernel.taps[size_t(k + radius)] = tap;
      sum += tap;
    }
    for (double& tap : term.kernel.taps) tap /= sum;
    // The 2-D kernel of this term is separable, g(x) g(y), and sums to amplitude * sum^2.
    term.weight = a * std::sqrt(kPi / b) * sum * sum;
    total += term.weight;
    terms.push_back(std::move(term));
  }
  for (CsfTerm& term : terms) term.weight /= total;
  return terms;
}

}  // namespace

int csf_radius(double ppd) {
  return static_cast<int>(std::ceil(3.0 * std::sqrt(kWidestB / (2.0 * kPi * kPi)) * ppd));
}

Plane csf_filter(const Plane& input, OpponentChannel channel, double ppd) {
  Plane out(input.width, input.height);
  for (const CsfTerm& term : csf_terms(kCsf[static_cast<size_t>(channel)], ppd)) {
    const Plane filtered = convolve_separable(input, term.kernel, term.kernel);
    for (size_t i = 0; i < out.values.size(); ++i) {
      out.values[i] += term.weight * filtered.values[i];
    }
  }
  return out;
}

}  // namespace ddgi::metrics
