#pragma once
// How many points a crossed medium gets (photons.march_points; each point costs a kNN query, so
// this is the march's cost per segment):
//   fixed        n, each weighing P / n: a segment of small P pays n queries for a small share
//   mass         ceil(n P) (at least 1), each weighing P / ceil(n P) <= 1 / n: the points follow
//                the segment's mass, so a thin segment pays one query, a thick one n
//   free_flight  n free flights stratified over the whole ray (stratum j of the unclipped
//                free-flight CDF), those inside the segment kept: n P points in expectation, each
//                weighing 1 / n. The collision gather is n = 1 of this.
// Every rule keeps the estimate unbiased: the count depends on the ray alone (mass), or only
// the stratum that straddles P is random (free_flight).
namespace vpm {

enum class MarchCount { fixed, mass, free_flight };

}  // namespace vpm
