#include "vsculpt/sketch/JoinFeaturePoints.h"

#include "CleanupGeometry.h"
#include "vsculpt/sketch/NaturalSpline.h"

#include <algorithm>
#include <functional>
#include <stdexcept>
#include <vector>

namespace vsculpt::sketch {

namespace {

JoinResult joinOpen(const Polyline2& older, Polyline2 newer, const JoinParams& params) {
    const Polyline2 curve = sampleNaturalSpline(older, false, params.samplesPerSpan);
    JoinResult result;
    std::vector<detail::Projection> proj;
    const auto projectAll = [&] {
        proj.clear();
        for (const glm::dvec2& p : newer)
            proj.push_back(detail::project(curve, p));
    };
    projectAll();
    const auto reverse = [&] {
        std::reverse(newer.begin(), newer.end());
        std::reverse(proj.begin(), proj.end());
        result.reversed = !result.reversed;
    };
    const auto on = [&](const detail::Projection& q) {
        return q.distance <= params.overlapDistance;
    };
    const auto interior = [&](const detail::Projection& q) {
        return on(q) && !q.atStart && !q.atEnd;
    };

    // Arc length of each older knot: knot i is sample i * samplesPerSpan unless the spline
    // merged coincident knots (then fall back to projecting, which is ambiguous only there).
    std::vector<double> knotS(older.size());
    const std::size_t sps = std::size_t(params.samplesPerSpan);
    if (curve.size() == (older.size() - 1) * sps + 1) {
        double acc = 0.0;
        for (std::size_t i = 0; i < curve.size(); ++i) {
            if (i > 0) acc += glm::distance(curve[i - 1], curve[i]);
            if (i % sps == 0) knotS[i / sps] = acc;
        }
    } else {
        for (std::size_t i = 0; i < older.size(); ++i)
            knotS[i] = detail::project(curve, older[i]).s;
    }

    // keep(s): which older knots survive, by arc length; newerFirst: newer goes before them.
    std::function<bool(double)> keep = [](double) { return true; };
    bool newerFirst = false;
    const detail::Projection& mid = proj[proj.size() / 2];
    if (interior(proj.front()) && interior(proj.back())) {
        if (newer.size() >= 3 && !on(mid) && (mid.atStart || mid.atEnd)) {
            // Both ends on the older curve, the middle out beyond one of its ends: the stroke
            // runs from near the older end round to near its start and closes a loop. Keep
            // the older stretch between the newer ends; the newer points follow it.
            if (proj.front().s < proj.back().s) reverse();
            const double sA = proj.front().s, sC = proj.back().s;
            keep = [=](double s) { return s > sC && s < sA; };
            result.overlap = Overlap::Closes;
        } else {
            if (proj.back().s < proj.front().s) reverse();
            const double sA = proj.front().s, sC = proj.back().s;
            keep = [=](double s) { return s < sA || s > sC; };
            result.overlap = Overlap::Full;
        }
    } else if (interior(proj.front()) || interior(proj.back())) {
        // One end on the older curve, the stroke leaves it past an end: that end is replaced.
        if (!interior(proj.front())) reverse();
        const double sA = proj.front().s;
        bool exitsAtEnd = true;
        for (std::size_t i = 1; i < proj.size(); ++i) {
            if (interior(proj[i])) continue;
            exitsAtEnd = proj[i].atEnd || (!proj[i].atStart && proj[i].s > sA);
            break;
        }
        if (exitsAtEnd) {
            keep = [=](double s) { return s < sA; };
        } else {
            reverse();  // run from beyond the start into the older curve
            keep = [=](double s) { return s > sA; };
            newerFirst = true;
        }
        result.overlap = Overlap::Partial;
    } else if (on(mid) && ((proj.front().atStart && proj.back().atEnd) ||
                           (proj.front().atEnd && proj.back().atStart))) {
        // Beyond both ends with the middle on the older curve: it covers all of it.
        if (proj.front().atEnd) reverse();
        keep = [](double) { return false; };
        result.overlap = Overlap::Full;
    } else {
        // Off the older curve: chain at the nearer end (seed rule (a)).
        const auto dist = [&](const glm::dvec2& p) {
            return std::min(glm::distance(p, newer.front()), glm::distance(p, newer.back()));
        };
        if (dist(older.back()) <= dist(older.front())) {
            if (glm::distance(newer.back(), older.back()) <
                glm::distance(newer.front(), older.back()))
                reverse();
        } else {
            if (glm::distance(newer.front(), older.front()) <
                glm::distance(newer.back(), older.front()))
                reverse();
            newerFirst = true;
        }
        result.overlap = Overlap::None;
    }

    if (params.newStrokeWeight < 1.0) {
        for (std::size_t i = 0; i < newer.size(); ++i)
            if (on(proj[i]))
                newer[i] = proj[i].point + params.newStrokeWeight * (newer[i] - proj[i].point);
    }
    const auto nearNewer = [&](const glm::dvec2& p) {
        return std::any_of(newer.begin(), newer.end(), [&](const glm::dvec2& q) {
            return glm::distance(p, q) < params.mergeDistance;
        });
    };
    Polyline2 before, after;
    for (std::size_t i = 0; i < older.size(); ++i) {
        if (!keep(knotS[i]) || nearNewer(older[i])) {
            ++result.olderRemoved;
            continue;
        }
        // Older knots before the newer span go first, those after it last.
        const bool isAfter =
            newerFirst || (result.overlap == Overlap::Full && knotS[i] > proj.back().s);
        (isAfter ? after : before).push_back(older[i]);
    }
    result.points = std::move(before);
    result.points.insert(result.points.end(), newer.begin(), newer.end());
    result.points.insert(result.points.end(), after.begin(), after.end());
    return result;
}

}  // namespace

JoinResult joinFeaturePoints(const Polyline2& older, bool olderClosed, const Polyline2& newer,
                             const JoinParams& params) {
    detail::requireFinite(older, "joinFeaturePoints");
    detail::requireFinite(newer, "joinFeaturePoints");
    if (newer.empty()) throw std::invalid_argument("joinFeaturePoints: empty newer sequence");
    if (older.size() < (olderClosed ? 3u : 2u))
        throw std::invalid_argument("joinFeaturePoints: older sequence too short");
    if (!(params.mergeDistance >= 0.0) || !(params.overlapDistance >= 0.0) ||
        !(params.newStrokeWeight >= 0.0) || !(params.newStrokeWeight <= 1.0) ||
        params.samplesPerSpan < 1)
        throw std::invalid_argument("joinFeaturePoints: invalid parameters");
    if (!olderClosed) return joinOpen(older, newer, params);

    // Open the loop at the older point farthest from the newer points, so the newer span never
    // straddles the seam; the seam point is repeated at the end while joining.
    const glm::dvec2 mid = newer[newer.size() / 2];
    std::size_t seam = 0;
    for (std::size_t i = 1; i < older.size(); ++i)
        if (glm::distance(older[i], mid) > glm::distance(older[seam], mid)) seam = i;
    Polyline2 opened(older.begin() + std::ptrdiff_t(seam), older.end());
    opened.insert(opened.end(), older.begin(), older.begin() + std::ptrdiff_t(seam));
    opened.push_back(older[seam]);
    JoinResult result = joinOpen(opened, newer, params);
    if (result.points.size() > 1 && result.points.front() == result.points.back())
        result.points.pop_back();
    else if (result.olderRemoved > 0)
        --result.olderRemoved;  // the repeated seam point was counted once too often
    return result;
}

}  // namespace vsculpt::sketch
