#include <sgfx/Viewer.h>
#include <gtest/gtest.h>
TEST(Smoke, Clear) {
    auto v = sgfx::Viewer::createHeadless(64, 64);
    v->camera()->clearColor = {0.5f, 0.25f, 1.0f, 1.0f};
    v->frame();
    auto img = v->capture();
    auto* p = img.pixel(10, 10);
    printf("%d %d %d %d\n", p[0], p[1], p[2], p[3]);
    printf("%s | %s\n", v->context().renderer().c_str(), v->context().version().c_str());
    for (auto& e : v->renderer().takeGlErrors()) printf("GLERR %s\n", e.c_str());
}
