// SPDX-License-Identifier: MIT
// What the sketch window draws: draw items as ink (roles tinted, widths and darkness kept),
// and the page's history (undone, deleted strokes) for reuse.
#include "vsculpt/app/SketchInkList.h"

#include <gtest/gtest.h>

using namespace vsculpt;

namespace {

studio::PenSample sample(double x, double y, double p, double t) {
    studio::PenSample s;
    s.view = glm::dvec2(x, y);
    s.pressure = p;
    s.time = t;
    return s;
}

int drawLine(studio::SketchPage& page, double y, double t0) {
    page.penDown(sample(0, y, 0.2, t0));
    page.penMove(sample(10, y, 0.6, t0 + 0.01));
    page.penMove(sample(20, y, 1.0, t0 + 0.02));
    return *page.penUp();
}

TEST(SketchInkList, DrawItemsBecomeInkWithRolesTinted) {
    studio::SketchPage page("p", "g");
    const int a = drawLine(page, 0, 0);
    const int b = drawLine(page, 10, 1);
    page.setStrokeRole(b, studio::Role::Outline);
    page.select({a});
    const std::vector<render::InkStroke> ink = app::inkOf(page);
    const std::vector<studio::DrawItem> items = page.drawList();
    ASSERT_EQ(ink.size(), items.size());
    ASSERT_EQ(ink.size(), 2u);
    for (size_t i = 0; i < ink.size(); ++i) {
        ASSERT_EQ(ink[i].pointsMm, items[i].points);
        ASSERT_EQ(ink[i].widthMm.size(), items[i].width.size());
        for (size_t k = 0; k < ink[i].widthMm.size(); ++k) {
            EXPECT_FLOAT_EQ(ink[i].widthMm[k], float(items[i].width[k]));
            EXPECT_FLOAT_EQ(ink[i].darkness[k], float(items[i].darkness[k]));
        }
    }
    EXPECT_EQ(ink[0].cls, render::InkClass::Selected);
    EXPECT_EQ(ink[1].cls, render::InkClass::Outline);
    // Pressure shows: the hard end is wider and darker than the light one.
    EXPECT_GT(ink[0].widthMm.back(), ink[0].widthMm.front());
    EXPECT_GT(ink[0].darkness.back(), ink[0].darkness.front());
}

TEST(SketchInkList, HistoryShowsUndoneAndDeletedStrokesForReuse) {
    studio::SketchPage page("p", "g");
    const int a = drawLine(page, 0, 0);
    const int b = drawLine(page, 10, 1);
    const int c = drawLine(page, 20, 2);
    EXPECT_TRUE(app::historyInk(page).empty());  // all live
    page.select({a});
    page.deleteSelection();
    page.undo();  // deletion undone: a is live again
    page.undo();  // c undone
    page.select({b});
    page.deleteSelection();  // b deleted (and c's redo dropped)
    const std::vector<render::InkStroke> past = app::historyInk(page);
    ASSERT_EQ(past.size(), 2u);  // b and c, not a
    for (const auto& s : past)
        EXPECT_EQ(s.cls, render::InkClass::Consumed);
    EXPECT_EQ(past[0].pointsMm.front(), glm::dvec2(0, 10));
    EXPECT_EQ(past[1].pointsMm.front(), glm::dvec2(0, 20));
    EXPECT_EQ(app::nearestHistoryStroke(page, {10, 19.5}, 1.0), c);
    EXPECT_EQ(app::nearestHistoryStroke(page, {10, 10.4}, 1.0), b);
    EXPECT_FALSE(app::nearestHistoryStroke(page, {10, 0}, 1.0));  // a is live
    EXPECT_FALSE(app::nearestHistoryStroke(page, {10, 15}, 1.0));
    const int reused = page.reuse(*app::nearestHistoryStroke(page, {10, 19.5}, 1.0));
    EXPECT_EQ(page.strokePoints(reused).front(), glm::dvec2(0, 20));
}

}  // namespace
