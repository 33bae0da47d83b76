#include "constraints/fit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace motionfork {

void Validate(const FitOptions& o) {
  auto bad = [](const std::string& field, double value, const std::string& rule) {
    throw std::invalid_argument("FitOptions." + field + " = " + std::to_string(value) +
                                " breaks the rule: " + rule);
  };
  if (!(o.low_percentile >= 0 && o.low_percentile <= 100)) {
    bad("low_percentile", o.low_percentile, "0 <= percent <= 100");
  }
  if (!(o.high_percentile >= 0 && o.high_percentile <= 100)) {
    bad("high_percentile", o.high_percentile, "0 <= percent <= 100");
  }
  if (!(o.low_percentile < o.high_percentile)) {
    bad("high_percentile", o.high_percentile,
        "must be > low_percentile (" + std::to_string(o.low_percentile) + ")");
  }
  if (!(o.margin_deg >= 0 && o.margin_deg <= 180))
    bad("margin_deg", o.margin_deg, "0 <= degrees <= 180");
  if (!(o.round_deg >= 0 && o.round_deg <= 10)) bad("round_deg", o.round_deg, "0 <= degrees <= 10");
  Validate(o.degeneracy);
}

double Percentile(std::vector<float>* values, double percent) {
  if (values->empty())
    throw std::invalid_argument("Percentile: expected at least one value, got 0");
  if (!(percent >= 0 && percent <= 100)) {
    throw std::invalid_argument("Percentile: expected 0 <= percent <= 100, got " +
                                std::to_string(percent));
  }
  const double rank = percent / 100.0 * static_cast<double>(values->size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(rank));
  std::nth_element(values->begin(), values->begin() + lo, values->end());
  const double x_lo = (*values)[lo];
  if (lo + 1 >= values->size() || rank == static_cast<double>(lo)) return x_lo;
  // The next order statistic is the minimum of the part after lo.
  const double x_hi = *std::min_element(values->begin() + lo + 1, values->end());
  return x_lo + (rank - static_cast<double>(lo)) * (x_hi - x_lo);
}

RangeFitter::RangeFitter(const ConstraintSet& set, const FitOptions& options)
    : set_(set), options_(options), checker_(set, options.degeneracy) {
  Validate(options_);
  samples_.resize(set.spec().constraints.size());
  degenerate_.assign(set.spec().constraints.size(), 0);
}

void RangeFitter::Add(const float* positions, int num_frames) {
  const int C = set_.num_constraints();
  angles_.resize(static_cast<size_t>(num_frames) * C);
  checker_.Run(positions, num_frames, angles_.data(), nullptr);
  for (int t = 0; t < num_frames; ++t) {
    const float* row = angles_.data() + static_cast<size_t>(t) * C;
    for (int c = 0; c < C; ++c) {
      const int s = set_.constraint(c).spec_index;
      if (row[c] == kUndefinedAngle) {
        ++degenerate_[s];
      } else {
        samples_[s].push_back(row[c]);
      }
    }
  }
  frames_ += num_frames;
}

void RangeFitter::Add(const Motion& motion) {
  if (motion.num_joints() != set_.num_joints()) {
    throw std::invalid_argument("RangeFitter: constraint set '" + set_.name() + "' was built for " +
                                std::to_string(set_.num_joints()) + " joints, got a motion with " +
                                std::to_string(motion.num_joints()));
  }
  Add(motion.positions().data(), motion.num_frames());
}

void RangeFitter::Merge(const RangeFitter& other) {
  if (&other.set_ != &set_ && other.set_.spec().constraints.size() != samples_.size()) {
    throw std::invalid_argument(
        "RangeFitter::Merge: the other fitter is for constraint set '" + other.set_.name() + "' (" +
        std::to_string(other.set_.spec().constraints.size()) + " definitions), this one for '" +
        set_.name() + "' (" + std::to_string(samples_.size()) + ")");
  }
  for (size_t s = 0; s < samples_.size(); ++s) {
    samples_[s].insert(samples_[s].end(), other.samples_[s].begin(), other.samples_[s].end());
    degenerate_[s] += other.degenerate_[s];
  }
  frames_ += other.frames_;
}

std::vector<FittedRange> RangeFitter::Fit() const {
  std::vector<FittedRange> out;
  const auto& specs = set_.spec().constraints;
  for (size_t s = 0; s < specs.size(); ++s) {
    FittedRange r;
    r.name = specs[s].name;
    r.samples = static_cast<long long>(samples_[s].size());
    r.degenerate = degenerate_[s];
    if (samples_[s].empty()) {
      throw std::invalid_argument("RangeFitter: constraint '" + r.name +
                                  "' has no defined angle in " + std::to_string(frames_) +
                                  " frames (" + std::to_string(r.degenerate) +
                                  " undefined); cannot fit its range");
    }
    std::vector<float> v = samples_[s];
    r.low_value_deg = Percentile(&v, options_.low_percentile);
    r.high_value_deg = Percentile(&v, options_.high_percentile);
    double lo = r.low_value_deg - options_.margin_deg;
    double hi = r.high_value_deg + options_.margin_deg;
    if (options_.round_deg > 0) {
      // Outwards, with a little slack so a value already on the grid stays there.
      lo = std::floor(lo / options_.round_deg + 1e-6) * options_.round_deg;
      hi = std::ceil(hi / options_.round_deg - 1e-6) * options_.round_deg;
    }
    if (specs[s].has_anatomical) {
      r.widened = specs[s].anatomical_lower_deg < lo || specs[s].anatomical_upper_deg > hi;
      lo = std::min(lo, specs[s].anatomical_lower_deg);
      hi = std::max(hi, specs[s].anatomical_upper_deg);
    }
    r.lower_deg = std::max(0.0, std::min(180.0, lo));
    r.upper_deg = std::max(0.0, std::min(180.0, hi));
    out.push_back(r);
  }
  return out;
}

ConstraintSetSpec WithFittedRanges(const ConstraintSetSpec& spec,
                                   const std::vector<FittedRange>& ranges) {
  ConstraintSetSpec out = spec;
  for (ConstraintSpec& c : out.constraints) {
    const auto it = std::find_if(ranges.begin(), ranges.end(),
                                 [&](const FittedRange& r) { return r.name == c.name; });
    if (it == ranges.end()) {
      throw std::invalid_argument("WithFittedRanges: no fitted range for constraint '" + c.name +
                                  "'");
    }
    c.has_range = true;
    // Rounding can leave e.g. 180.00000000000003; keep the bounds exactly in [0, 180].
    c.lower_deg = std::max(0.0, std::min(180.0, it->lower_deg));
    c.upper_deg = std::max(c.lower_deg, std::min(180.0, it->upper_deg));
    char buf[160];
    std::snprintf(
        buf, sizeof(buf), "fitted: %lld angles, percentiles %.2f .. %.2f deg%s%s", it->samples,
        it->low_value_deg, it->high_value_deg,
        it->degenerate ? (", " + std::to_string(it->degenerate) + " undefined").c_str() : "",
        it->widened ? ", widened to the anatomical limit" : "");
    c.range_comment = buf;
  }
  return out;
}

}  // namespace motionfork
