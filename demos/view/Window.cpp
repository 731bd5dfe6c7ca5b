// sgfx-view's window: GLFW input drives an orbit or fly manipulator; Dear ImGui (Debian's
// libimgui-dev, when it was found at configure time) draws the effects panel and the stats
// overlay over the view through the viewer's final draw callback. ImGui's OpenGL backend loads
// the system libGL itself at run time, and only here, so headless runs never touch it. A left
// click that does not drag picks (sgfx::pick): the overlay shows what the pixel shows.
#include "AnimationControls.h"
#include "Options.h"
#include "ViewScene.h"

#include <sgfx/GraphicsContext.h>
#include <sgfx/Image.h>
#include <sgfx/Manipulator.h>
#include <sgfx/Queries.h>
#include <sgfx/Viewer.h>
#include <sgfx/Visitors.h>

#include <sgfx_glad/gl.h>
// After glad: GLFW must not pull in the system GL header.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#if SGFX_VIEW_IMGUI
#include <dlfcn.h>

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace view {

namespace {

// What the GLFW callbacks leave for the frame loop.
struct Input {
    std::deque<int> keys; // pressed keys, in order
    std::vector<std::string> dropped;
    double scroll = 0.0;
    std::optional<glm::dvec2> pressedAt; // the left button's, in window coordinates
    std::vector<glm::dvec2> clicks;      // left clicks that did not drag, in window coordinates
};

// A press and release of the left button this close together (window coordinates) is a click,
// not an orbit drag.
constexpr double kClickSlop = 3.0;

Input& inputOf(GLFWwindow* w) {
    return *static_cast<Input*>(glfwGetWindowUserPointer(w));
}

using sgfx::CameraManipulator;

struct Stats {
    double fps = 0.0, frameMs = 0.0;
    sgfx::FrameStats last;
};

class App {
public:
    App(const Options& o, ViewScene& scene, sgfx::Viewer& viewer, GLFWwindow* win)
        : o_(o)
        , s_(o.settings)
        , scene_(scene)
        , viewer_(viewer)
        , win_(win) {
        home();
        anim_.attach(*scene_.model());
    }

    void home() {
        const auto& vp = viewer_.camera()->viewport;
        orbit_.home(scene_.boundsMin(), scene_.boundsMax(), kFovy, vp.aspect(), o_.yaw, o_.pitch);
        fly_.home(scene_.boundsMin(), scene_.boundsMax(), kFovy, vp.aspect(), o_.yaw, o_.pitch);
        viewer_.camera()->resetHistory();
    }
    CameraManipulator& manipulator() { return flying_ ? static_cast<CameraManipulator&>(fly_) : orbit_; }
    void toggleFlying() {
        // The new manipulator takes over the view as it is.
        CameraManipulator& from = manipulator();
        flying_ = !flying_;
        manipulator().setLookAt(from.eye(), from.target());
    }

    void key(int k) {
        static const sgfx::AntiAliasing cycle[] = {sgfx::AntiAliasing::none(),   sgfx::AntiAliasing::msaa(4),
                                                   sgfx::AntiAliasing::ssaa(2),  sgfx::AntiAliasing::fxaa(),
                                                   sgfx::AntiAliasing::taa(),    sgfx::AntiAliasing::smaa(),
                                                   sgfx::AntiAliasing::smaaT2x()};
        switch (k) {
        case GLFW_KEY_ESCAPE:
            glfwSetWindowShouldClose(win_, GLFW_TRUE);
            break;
        case GLFW_KEY_H:
            home();
            break;
        case GLFW_KEY_V:
            toggleFlying();
            break;
        case GLFW_KEY_F:
            s_.fog = !s_.fog;
            break;
        case GLFW_KEY_O:
            s_.ao = !s_.ao;
            break;
        case GLFW_KEY_M:
            s_.antiAliasing = cycle[(std::size_t(s_.antiAliasing.mode) + 1) % std::size(cycle)];
            break;
        case GLFW_KEY_R:
            s_.weather = Weather((int(s_.weather) + 1) % 3);
            break;
        case GLFW_KEY_K:
            s_.sky = !s_.sky;
            break;
        case GLFW_KEY_G:
            s_.ground = !s_.ground;
            break;
        case GLFW_KEY_L: // H is home
            s_.shadows = !s_.shadows;
            break;
        case GLFW_KEY_F1:
            panel_ = !panel_;
            break;
        case GLFW_KEY_SPACE:
            anim_.togglePlay();
            break;
        case GLFW_KEY_N:
            anim_.next();
            break;
        case GLFW_KEY_F12:
        case GLFW_KEY_P:
            screenshot();
            break;
        default:
            break;
        }
    }

    std::string screenshot(std::string path = {}) {
        if (path.empty()) {
            const std::string stem =
                o_.out.size() > 4 && o_.out.ends_with(".png") ? o_.out.substr(0, o_.out.size() - 4) : o_.out;
            path = stem + "-" + std::to_string(++shots_) + ".png";
        }
        try {
            viewer_.writeScreenshot(path);
            message_ = "wrote " + path;
        } catch (const std::exception& e) {
            message_ = std::string("screenshot failed: ") + e.what();
        }
        std::printf("%s\n", message_.c_str());
        return path;
    }

    void load(const std::vector<std::string>& files) {
        try {
            scene_.setModel(loadFiles(files, o_));
            home();
            anim_.attach(*scene_.model());
            message_ = "loaded " + files.front() + (files.size() > 1 ? " and more" : "");
        } catch (const std::exception& e) {
            message_ = e.what(); // the old model stays
        }
        std::printf("%s\n", message_.c_str());
    }

    // What the clicked pixel shows, with the camera as last drawn (what the user clicked on).
    // (x, y): window coordinates, turned into framebuffer pixels (they differ on HiDPI screens).
    void pick(glm::dvec2 at) {
        int ww = 0, wh = 0, fw = 0, fh = 0;
        glfwGetWindowSize(win_, &ww, &wh);
        glfwGetFramebufferSize(win_, &fw, &fh);
        if (ww <= 0 || wh <= 0) return;
        const double x = at.x * fw / ww, y = at.y * fh / wh;
        pick_ = scene_.describePick(sgfx::pick(viewer_, x, y), x, y);
        std::printf("%s\n", pick_.c_str());
        std::fflush(stdout);
    }

    // Mouse and keys held down this frame (ImGui takes them while the pointer is over the panel).
    void pollHeld(double dt, bool mouseFree, bool keysFree, Input& in) {
        double x = 0, y = 0;
        glfwGetCursorPos(win_, &x, &y);
        const glm::vec2 delta(float(x - lastX_), float(y - lastY_));
        lastX_ = x, lastY_ = y;
        const float h = float(std::max(1, viewer_.camera()->viewport.height));
        if (mouseFree && haveCursor_) {
            if (glfwGetMouseButton(win_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS)
                manipulator().drag(sgfx::MouseButton::Left, delta, h);
            if (glfwGetMouseButton(win_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS)
                manipulator().drag(sgfx::MouseButton::Right, delta, h);
            if (glfwGetMouseButton(win_, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS)
                manipulator().drag(sgfx::MouseButton::Middle, delta, h);
            if (in.scroll != 0.0) manipulator().scroll(float(in.scroll));
        }
        haveCursor_ = true;
        in.scroll = 0.0;
        if (!keysFree) return;
        auto held = [&](int k) { return glfwGetKey(win_, k) == GLFW_PRESS ? 1.0f : 0.0f; };
        const glm::vec3 axes(held(GLFW_KEY_D) - held(GLFW_KEY_A), held(GLFW_KEY_W) - held(GLFW_KEY_S),
                             held(GLFW_KEY_E) - held(GLFW_KEY_Q));
        const bool fast = held(GLFW_KEY_LEFT_SHIFT) + held(GLFW_KEY_RIGHT_SHIFT) > 0.0f;
        if (axes != glm::vec3(0.0f)) manipulator().move(axes, float(dt), fast);
    }

    // Pushes settings and the view into the graph; a refused setting is reported and undone.
    void applyFrame() {
        try {
            scene_.apply(s_, *viewer_.camera());
            applied_ = s_;
        } catch (const std::invalid_argument& e) {
            message_ = e.what();
            std::fprintf(stderr, "sgfx-view: %s\n", e.what());
            s_ = applied_;
            scene_.apply(s_, *viewer_.camera());
        }
        CameraManipulator& m = manipulator();
        m.apply(*viewer_.camera());
        // Clip planes around the model at whatever distance the eye is.
        const float r = scene_.radius();
        const float d = glm::length(m.eye() - 0.5f * (scene_.boundsMin() + scene_.boundsMax()));
        const float zNear = std::max(1e-3f * r, 0.2f * std::max(d - 4.0f * r, 0.05f * r));
        viewer_.camera()->setPerspective(kFovy, zNear, std::max(d, r) * 80.0f + 100.0f * r);
    }

    void recordStats(double dt) {
        stats_.last = viewer_.stats();
        const double a = 0.1; // smoothed over about ten frames
        stats_.frameMs = stats_.frameMs == 0.0 ? 1e3 * dt : (1.0 - a) * stats_.frameMs + a * 1e3 * dt;
        stats_.fps = stats_.frameMs > 0.0 ? 1e3 / stats_.frameMs : 0.0;
    }

    std::string titleLine() const {
        char t[256];
        std::snprintf(t, sizeof t, "sgfx-view — %.1f FPS, %.1f ms, %zu draws, %zu triangles — %s", stats_.fps,
                      stats_.frameMs, stats_.last.drawCalls, stats_.last.triangles,
                      scene_.describeEffects(s_).c_str());
        return t;
    }

#if SGFX_VIEW_IMGUI
    // The panel and the stats overlay; ImGui::Render() happens in the final draw callback.
    void buildUi() {
        const sgfx::FrameStats& f = stats_.last;
        const auto& vp = viewer_.camera()->viewport;
        ImGui::SetNextWindowPos({8.0f, float(vp.height) - 8.0f}, ImGuiCond_Always, {0.0f, 1.0f});
        ImGui::SetNextWindowBgAlpha(0.6f);
        ImGui::Begin("stats", nullptr,
                     ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                         ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoFocusOnAppearing |
                         ImGuiWindowFlags_NoNav);
        ImGui::Text("%.1f FPS  %.2f ms", stats_.fps, stats_.frameMs);
        ImGui::Text("CPU cull %.2f ms  draw %.2f ms", f.cullMs, f.drawMs);
        ImGui::Text("%zu draw calls  %zu triangles", f.drawCalls, f.triangles);
        ImGui::Text("%s camera, %s", flying_ ? "fly" : "orbit", viewer_.context().renderer().c_str());
        if (!f.passTimes.empty()) {
            ImGui::Separator();
            ImGui::TextUnformatted("GPU ms per pass");
            for (const auto& p : f.passTimes)
                ImGui::Text("%7.3f  %s", p.gpuMs, p.name.c_str());
        }
        if (!message_.empty()) {
            ImGui::Separator();
            ImGui::TextWrapped("%s", message_.c_str());
        }
        ImGui::Separator();
        ImGui::PushTextWrapPos(ImGui::GetFontSize() * 40.0f);
        ImGui::TextUnformatted(pick_.empty() ? "click to pick" : pick_.c_str());
        ImGui::PopTextWrapPos();
        ImGui::End();
        if (!panel_) return;

        ImGui::SetNextWindowPos({float(vp.width) - 8.0f, 8.0f}, ImGuiCond_Always, {1.0f, 0.0f});
        ImGui::SetNextWindowSize({300, 0}, ImGuiCond_FirstUseEver);
        ImGui::Begin("Effects (F1 hides)");
        if (ImGui::CollapsingHeader("Fog", ImGuiTreeNodeFlags_DefaultOpen)) {
            ImGui::Checkbox("fog (F)", &s_.fog);
            int mode = int(s_.fogMode);
            if (ImGui::Combo("mode", &mode, "forward\0split (seed 2)\0post-process (seed 1)\0"))
                s_.fogMode = sgfx::FogMode(mode);
            int preset = int(s_.fogPreset);
            if (ImGui::Combo("preset", &preset, "scaled to the model\0solid (fig. 1)\0ground (fig. 1)\0")) {
                s_.fogPreset = FogPreset(preset);
                s_.fogDensity = s_.fogFalloff = 0.0f;
            }
            const sgfx::FogParameters p = scene_.fogParameters(s_);
            float rho = p.density, b = p.falloff;
            if (ImGui::SliderFloat("rho0 (1/m)", &rho, 1e-6f, 10.0f, "%.2e", ImGuiSliderFlags_Logarithmic))
                s_.fogDensity = rho;
            if (ImGui::SliderFloat("b (1/m)", &b, 1e-5f, 100.0f, "%.2e", ImGuiSliderFlags_Logarithmic))
                s_.fogFalloff = b;
        }
        if (ImGui::CollapsingHeader("Ambient occlusion")) {
            ImGui::Checkbox("AO (O)", &s_.ao);
            ImGui::SliderInt("samples", &s_.aoSamples, 8, 64);
            float radius = scene_.aoParameters(s_).radius;
            if (ImGui::SliderFloat("radius (m)", &radius, 1e-3f * scene_.radius(), scene_.radius(), "%.3g",
                                   ImGuiSliderFlags_Logarithmic))
                s_.aoRadius = radius;
        }
        if (ImGui::CollapsingHeader("Anti-aliasing")) {
            static const sgfx::AntiAliasing modes[] = {
                sgfx::AntiAliasing::none(),   sgfx::AntiAliasing::msaa(4), sgfx::AntiAliasing::ssaa(2),
                sgfx::AntiAliasing::fxaa(),   sgfx::AntiAliasing::taa(),   sgfx::AntiAliasing::smaa(),
                sgfx::AntiAliasing::smaaT2x()};
            int aa = int(s_.antiAliasing.mode);
            if (ImGui::Combo("mode (M)", &aa, "none\0MSAA 4x\0SSAA 2x\0FXAA\0TAA\0SMAA\0SMAA T2x\0"))
                s_.antiAliasing = modes[aa];
        }
        if (ImGui::CollapsingHeader("Particles and sky")) {
            int w = int(s_.weather);
            if (ImGui::Combo("weather (R)", &w, "none\0rain\0snow\0")) s_.weather = Weather(w);
            ImGui::Checkbox("sky (K)", &s_.sky);
            ImGui::SliderFloat("solar time (h)", &s_.skyHours, 4.0f, 20.0f, "%.1f");
            ImGui::Checkbox("ground (G)", &s_.ground);
            // The file given with --env stays selectable once loaded.
            int env = int(s_.env);
            const bool hasFile = !s_.envFile.empty();
            if (ImGui::Combo("environment light", &env, hasFile ? "none\0sky\0file\0" : "none\0sky\0"))
                s_.env = EnvSource(env);
            ImGui::SliderFloat("environment intensity", &s_.envIntensity, 0.0f, 4.0f, "%.2f");
        }
        if (ImGui::CollapsingHeader("Shadows")) {
            ImGui::Checkbox("shadows (L)", &s_.shadows);
            int filter = int(s_.shadowFilter);
            if (ImGui::Combo("filter", &filter, "hard (2x2 bilinear)\0PCF (16 taps)\0PCSS (soft)\0"))
                s_.shadowFilter = sgfx::ShadowFilter(filter);
            ImGui::Checkbox("tint by cascade", &s_.shadowCascades);
        }
        if (!anim_.empty()) animationUi();
        if (ImGui::CollapsingHeader("Camera", ImGuiTreeNodeFlags_DefaultOpen)) {
            if (ImGui::Button(flying_ ? "orbit (V)" : "fly (V)")) toggleFlying();
            ImGui::SameLine();
            if (ImGui::Button("home (H)")) home();
            ImGui::SameLine();
            if (ImGui::Button("screenshot (F12)")) screenshot();
            bool timing = viewer_.renderer().options().timePasses;
            if (ImGui::Checkbox("GPU timer per pass", &timing))
                viewer_.renderer().options().timePasses = timing;
        }
        ImGui::End();
    }

    // The timeline: which animation, play/pause, a time slider that scrubs (paused while dragged),
    // speed, loop or clamp.
    void animationUi() {
        if (!ImGui::CollapsingHeader("Animation", ImGuiTreeNodeFlags_DefaultOpen)) return;
        const auto& entries = anim_.entries();
        const int sel = anim_.selected();
        if (ImGui::BeginCombo("animation (N)", sel >= 0 ? entries[std::size_t(sel)].label.c_str() : "")) {
            for (std::size_t e = 0; e < entries.size(); ++e) {
                ImGui::PushID(int(e));
                if (ImGui::Selectable(entries[e].label.c_str(), int(e) == sel)) anim_.select(e);
                ImGui::PopID();
            }
            ImGui::EndCombo();
        }
        if (ImGui::Button(anim_.playing() ? "pause (Space)" : "play (Space)")) anim_.togglePlay();
        ImGui::SameLine();
        bool loop = anim_.loop();
        if (ImGui::Checkbox("loop (else clamp)", &loop)) anim_.setLoop(loop);
        float t = float(anim_.time());
        const float d = std::max(float(anim_.duration()), 1e-3f);
        const bool moved = ImGui::SliderFloat("time (s)", &t, 0.0f, d, "%.3f");
        if (ImGui::IsItemActivated()) anim_.beginScrub();
        if (moved) anim_.scrub(double(t));
        if (ImGui::IsItemDeactivated()) anim_.endScrub();
        ImGui::Text("%.3f / %.3f s", anim_.time(), anim_.duration());
        float speed = float(anim_.speed());
        if (ImGui::SliderFloat("speed", &speed, -2.0f, 4.0f, "%.2fx")) anim_.setSpeed(double(speed));
    }
#endif

    // --self-test: what a user would do, at fixed points of the run.
    void script(int frame, int frames, Input& in) {
        const int step = std::max(1, frames / 12);
        const float h = float(viewer_.camera()->viewport.height);
        if (frame < frames / 4) manipulator().drag(sgfx::MouseButton::Left, {6.0f, 1.0f}, h);
        if (frame == 1) { // a click at the window's centre, where the orbit camera looks at the model
            int ww = 0, wh = 0;
            glfwGetWindowSize(win_, &ww, &wh);
            in.clicks.push_back({0.5 * ww, 0.5 * wh});
        }
        if (frame == step) in.scroll += 2.0;
        if (frame == 2 * step) in.keys.insert(in.keys.end(), {GLFW_KEY_F, GLFW_KEY_O, GLFW_KEY_M});
        if (frame == 3 * step) in.keys.insert(in.keys.end(), {GLFW_KEY_R, GLFW_KEY_K, GLFW_KEY_L});
        if (frame == 4 * step) {
            s_.fogMode = sgfx::FogMode::PostProcess;
            s_.aoSamples = 16;
        }
        if (frame == 5 * step) {
            glfwSetWindowSize(win_, o_.width * 3 / 4, o_.height * 3 / 4);
            resized_ = true;
        }
        if (frame == 6 * step) in.keys.push_back(GLFW_KEY_V); // fly
        if (frame > 6 * step && frame < 8 * step) manipulator().move({0.3f, 1.0f, 0.1f}, 1.0f / 60.0f, false);
        if (frame == 8 * step) in.keys.insert(in.keys.end(), {GLFW_KEY_M, GLFW_KEY_R, GLFW_KEY_H});
        if (frame == 9 * step) {
            s_.fogFalloff = 1e9f; // refused by the fog node: reported, the last settings kept
        }
        if (frame == 10 * step) in.dropped.assign(o_.files.begin(), o_.files.end());
        if (!anim_.empty()) scriptAnimation(frame, step, in);
    }
    // The timeline's controls, on an animated model: pause, scrub, cycle, loop off, play.
    void scriptAnimation(int frame, int step, Input& in) {
        if (frame == step) in.keys.push_back(GLFW_KEY_SPACE);
        if (frame == 2 * step) anim_.beginScrub();
        if (frame > 2 * step && frame < 3 * step) anim_.scrub(anim_.duration() * (frame - 2 * step) / step);
        if (frame == 3 * step) anim_.endScrub();
        if (frame == 4 * step) in.keys.push_back(GLFW_KEY_N);
        if (frame == 5 * step) {
            anim_.setLoop(false);
            anim_.setSpeed(1.5);
            in.keys.push_back(GLFW_KEY_SPACE);
        }
    }
    const AnimationControls& animation() const {
        return anim_;
    }

    bool resized() const {
        return resized_;
    }
    bool flying() const {
        return flying_;
    }
    const Settings& settings() const {
        return s_;
    }
    const std::string& message() const {
        return message_;
    }
    int shots() const {
        return shots_;
    }
    static constexpr float kFovy = 40.0f;

private:
    const Options& o_;
    Settings s_, applied_;
    ViewScene& scene_;
    sgfx::Viewer& viewer_;
    GLFWwindow* win_;
    sgfx::OrbitManipulator orbit_;
    sgfx::FlyManipulator fly_;
    bool flying_ = false, panel_ = true, haveCursor_ = false, resized_ = false;
    double lastX_ = 0, lastY_ = 0;
    Stats stats_;
    AnimationControls anim_;
    std::string message_, pick_;
    int shots_ = 0;
};

// The GLFW callbacks fill `input`. Installed before ImGui's, which chains to them.
void listen(GLFWwindow* win, Input& input) {
    glfwSetWindowUserPointer(win, &input);
    glfwSetKeyCallback(win, [](GLFWwindow* w, int key, int, int action, int) {
        if (action == GLFW_PRESS) inputOf(w).keys.push_back(key);
    });
    glfwSetScrollCallback(win, [](GLFWwindow* w, double, double dy) { inputOf(w).scroll += dy; });
    glfwSetMouseButtonCallback(win, [](GLFWwindow* w, int button, int action, int) {
        if (button != GLFW_MOUSE_BUTTON_LEFT) return;
        Input& in = inputOf(w);
        glm::dvec2 at(0.0);
        glfwGetCursorPos(w, &at.x, &at.y);
        if (action == GLFW_PRESS) in.pressedAt = at;
        if (action == GLFW_RELEASE && in.pressedAt && glm::length(at - *in.pressedAt) <= kClickSlop)
            in.clicks.push_back(at);
        if (action == GLFW_RELEASE) in.pressedAt.reset();
    });
    glfwSetDropCallback(win, [](GLFWwindow* w, int count, const char** paths) {
        auto& d = inputOf(w).dropped;
        d.assign(paths, paths + count);
    });
}

#if SGFX_VIEW_IMGUI
void startImGui(GLFWwindow* win) {
    // ImGui's GL loader dlopens the system libGL and closes it at shutdown; this process-lifetime
    // reference keeps the library (and glvnd's dispatch stubs it made for ImGui) loaded, so
    // nothing of it is unloaded while still referenced and leak reports can name it.
    static void* const keepLibGl = dlopen("libGL.so.1", RTLD_LAZY | RTLD_LOCAL);
    (void)keepLibGl;
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr; // no imgui.ini written next to the user's files
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(win, true);
    if (!ImGui_ImplOpenGL3_Init("#version 450"))
        throw sgfx::ContextError("sgfx-view: Dear ImGui's OpenGL backend could not start");
}
#endif

} // namespace

int runWindow(const Options& o, ViewScene& scene) {
    auto window = std::make_unique<sgfx::GlfwWindow>(o.width, o.height, "sgfx-view");
    GLFWwindow* win = window->handle();
    sgfx::Viewer viewer(std::move(window));
    viewer.renderer().options().timePasses = true;
    viewer.setSceneData(scene.root());

    Input input;
    listen(win, input);

    App app(o, scene, viewer, win);
#if SGFX_VIEW_IMGUI
    startImGui(win);
    std::size_t uiVertices = 0;
    bool grabWindow = false;
    sgfx::Image windowImage; // --self-test: what the window shows, panel included
    viewer.finalDrawCallback = [&](sgfx::Viewer& v) {
        ImGui::Render();
        ImDrawData* d = ImGui::GetDrawData();
        uiVertices = std::size_t(d->TotalVtxCount);
        ImGui_ImplOpenGL3_RenderDrawData(d);
        if (!grabWindow) return;
        windowImage = sgfx::Image{v.context().width(), v.context().height(), 4, {}};
        windowImage.pixels.resize(std::size_t(windowImage.width) * std::size_t(windowImage.height) * 4);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadBuffer(GL_BACK);
        glReadPixels(0, 0, windowImage.width, windowImage.height, GL_RGBA, GL_UNSIGNED_BYTE,
                     windowImage.pixels.data());
        for (int y = 0; y < windowImage.height / 2; ++y) // GL's rows go bottom up
            std::swap_ranges(windowImage.pixel(0, y), windowImage.pixel(0, y + 1),
                             windowImage.pixel(0, windowImage.height - 1 - y));
    };
#endif
    std::printf("window: left click pick, left drag orbit/look, right drag zoom, middle drag pan, wheel "
                "zoom, WASD/QE move, V orbit/fly, H home, F fog, O AO, M anti-aliasing, R weather, "
                "K sky, G ground, L shadows, Space play/pause, N next animation, F1 panel, F12 screenshot, "
                "Esc quit; drop files to load them\n");
    std::fflush(stdout);

    const int startW = viewer.context().width(), startH = viewer.context().height();
    double last = glfwGetTime(), titleTime = last;
    int frames = 0;
    while (!glfwWindowShouldClose(win)) {
        glfwPollEvents();
        const double now = glfwGetTime();
        const double dt = o.selfTestFrames ? 1.0 / 60.0 : std::clamp(now - last, 1e-4, 0.25);
        last = now;
        if (o.selfTestFrames) app.script(frames, o.selfTestFrames, input);

        bool mouseFree = true, keysFree = true;
#if SGFX_VIEW_IMGUI
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        mouseFree = !ImGui::GetIO().WantCaptureMouse;
        keysFree = !ImGui::GetIO().WantCaptureKeyboard;
#endif
        while (!input.keys.empty()) {
            if (keysFree) app.key(input.keys.front());
            input.keys.pop_front();
        }
        if (!input.dropped.empty()) {
            app.load(input.dropped);
            input.dropped.clear();
        }
        for (const glm::dvec2& click : input.clicks)
            if (mouseFree) app.pick(click);
        input.clicks.clear();
        app.pollHeld(dt, mouseFree, keysFree, input);
#if SGFX_VIEW_IMGUI
        app.buildUi();
#endif
        app.applyFrame();
#if SGFX_VIEW_IMGUI
        grabWindow = o.selfTestFrames && frames + 1 == o.selfTestFrames;
#endif
        viewer.frame(dt);
        app.recordStats(dt);
        for (const std::string& e : viewer.renderer().takeGlErrors())
            std::fprintf(stderr, "sgfx-view: GL: %s\n", e.c_str());
        for (const std::string& w : viewer.renderer().takeWarnings())
            std::fprintf(stderr, "sgfx-view: warning: %s\n", w.c_str());
        ++frames;
        if (now - titleTime > 0.5 || o.selfTestFrames) {
            glfwSetWindowTitle(win, app.titleLine().c_str());
            titleTime = now;
        }
        if (o.selfTestFrames && frames >= o.selfTestFrames) break;
    }

    int status = 0;
    if (o.selfTestFrames) {
        const std::string shot = app.screenshot(o.out);
        const sgfx::Image img = viewer.capture();
        const int w = viewer.context().width(), h = viewer.context().height();
        std::printf("window: %d frames, %dx%d -> %dx%d, capture %dx%d, %s camera, effects: %s, screenshot %s",
                    frames, startW, startH, w, h, img.width, img.height, app.flying() ? "fly" : "orbit",
                    scene.describeEffects(app.settings()).c_str(), shot.c_str());
        if (!app.animation().empty())
            std::printf(", animation %s at %.3f s %s",
                        app.animation().entries()[std::size_t(app.animation().selected())].label.c_str(),
                        app.animation().time(), app.animation().playing() ? "playing" : "paused");
#if SGFX_VIEW_IMGUI
        std::printf(", panel %zu vertices", uiVertices);
        if (!windowImage.pixels.empty()) {
            const std::string stem = o.out.ends_with(".png") ? o.out.substr(0, o.out.size() - 4) : o.out;
            sgfx::writePng(stem + "-window.png", windowImage);
            std::printf(", window %s-window.png", stem.c_str());
        }
#endif
        std::printf("\n");
        std::fflush(stdout); // before the leak checker's exit, which skips stdio's flush
        if (img.width != w || img.height != h) {
            std::fprintf(stderr, "sgfx-view: the scene target (%dx%d) did not follow the window (%dx%d)\n",
                         img.width, img.height, w, h);
            status = 1;
        }
    }
#if SGFX_VIEW_IMGUI
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    viewer.finalDrawCallback = nullptr;
#endif
    return status;
}

} // namespace view
