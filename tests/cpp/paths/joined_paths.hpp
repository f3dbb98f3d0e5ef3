// The beads of planned paths with connected insets (paths/connected_insets.hpp) split back into
// what the path-geometry tests measure: every ring part as a closed polyline (its repeated end
// point dropped), every open piece as an open polyline, and the links apart with the two beads
// each one joins.
#pragma once

#include <cstddef>
#include <vector>

#include "curvedslicer/paths/connected_insets.hpp"
#include "curvedslicer/paths/polyline.hpp"
#include "curvedslicer/plan/plan.hpp"

namespace curvedslicer::testing {

struct LinkPart {
  Polyline line;       ///< the step-over, its end points on the beads it joins
  std::size_t before;  ///< index into SplitBeads::beads of the ring part it leaves
  std::size_t after;   ///< index of the ring part it reaches
};

struct SplitBeads {
  std::vector<Polyline> beads;  ///< ring parts (closed) and open pieces, in deposition order
  std::vector<LinkPart> links;
  std::size_t rings = 0;  ///< ring parts (and closed paths) among `beads`
};

inline Polyline pointsOf(const PlanPath& path, std::size_t first, std::size_t last) {
  Polyline line;
  for (std::size_t i = first; i <= last; ++i) line.points.push_back(path.points[i].position);
  return line;
}

/// Splits every path of a layer (see the file comment).
inline SplitBeads splitLayerBeads(const std::vector<PlanPath>& paths) {
  SplitBeads out;
  for (const PlanPath& path : paths) {
    const std::vector<JoinedPathPart> parts = splitJoinedPath(path);
    for (const JoinedPathPart& part : parts) {
      if (!part.ring) {
        const bool isLink =
            parts.size() > 1 && part.first > 0 && part.last + 1 < path.points.size();
        if (isLink) {
          out.links.push_back(
              {pointsOf(path, part.first, part.last), out.beads.size() - 1, out.beads.size()});
          continue;
        }
        out.beads.push_back(pointsOf(path, part.first, part.last));
        continue;
      }
      Polyline ring = pointsOf(path, part.first, path.closed ? part.last : part.last - 1);
      ring.closed = true;
      out.beads.push_back(std::move(ring));
      ++out.rings;
    }
  }
  return out;
}

}  // namespace curvedslicer::testing
