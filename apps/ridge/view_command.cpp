// `ridge view ARCHIVE`: the interactive fly-through. Parse, open a window, then per frame map
// GLFW input onto FlyCamera and RenderSettings, draw with TerrainRenderer and lay a Dear ImGui
// stats overlay over it. Everything terrain-related lives in libridge; this file is input
// plumbing and the overlay.
#include "camera_readout.h"
#include "commands.h"
#include "range_check.h"
#include "render_args.h"
#include "terminal.h"

#include "ridge/core/error.h"
#include "ridge/lod/archive_frame.h"
#include "ridge/lod/camera_path.h"
#include "ridge/lod/ellipsoid.h"

#include <fmt/core.h>

#include <charconv>
#include <cstdlib>

#if RIDGE_HAVE_VIEWER
#include "ridge/archive/archive_reader.h"
#include "ridge/core/sanitizer.h"
#include "ridge/gpu/context.h"
#include "ridge/io/raster_writer.h"
#include "ridge/render/fly_camera.h"
#include "ridge/render/legend.h"
#include "ridge/render/orbit_camera.h"
#include "ridge/render/terrain_renderer.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE // GL declarations come from epoxy
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#if RIDGE_ADDRESS_SANITIZER
#include <sanitizer/lsan_interface.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <vector>
#endif

namespace ridge::cli {

namespace {

constexpr double kMinEpsilonPx = 0.25, kMaxEpsilonPx = 16.0;
constexpr double kDegreesPerRadian = 180.0 / 3.14159265358979323846;

#if RIDGE_HAVE_VIEWER
// `text` as one shell word: as is when it holds only safe characters, else single-quoted.
std::string shellQuoted(const std::string& text)
{
    const bool safe = !text.empty() &&
                      text.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                             "0123456789_-+./:=@%,") == std::string::npos;
    if (safe)
        return text;
    std::string out = "'";
    for (char c : text)
        out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

// Dear ImGui with its GLFW and OpenGL 3 backends, for one window. Must be created after the
// window's context and destroyed before it (it owns GL objects). Installs ImGui's GLFW
// callbacks, which chain to the ones already set on the window.
class ImGuiSession {
  public:
    explicit ImGuiSession(GLFWwindow* window)
    {
        IMGUI_CHECKVERSION();
        ImGui::CreateContext();
        // No imgui.ini in whatever directory the user ran ridge from.
        ImGui::GetIO().IniFilename = nullptr;
        ImGui::StyleColorsDark();
        if (!ImGui_ImplGlfw_InitForOpenGL(window, true) ||
            !ImGui_ImplOpenGL3_Init("#version 450")) {
            ImGui::DestroyContext();
            throw Error("ridge view: cannot initialise the Dear ImGui overlay");
        }
    }
    ~ImGuiSession()
    {
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
    }
    ImGuiSession(const ImGuiSession&) = delete;
    ImGuiSession& operator=(const ImGuiSession&) = delete;
};

// Discrete input between two frames, filled by GLFW callbacks (main thread, inside
// pollEvents) and consumed by the frame loop.
struct PendingInput {
    double scroll = 0.0; // wheel notches, + = away from the user
    std::vector<int> pressed_keys;
};

void onScroll(GLFWwindow* window, double /*x*/, double y)
{
    // ImGui's callback runs after this one (it chains), so its WantCaptureMouse is last frame's:
    // good enough to keep the wheel for scrolling the overlay when hovering it.
    if (ImGui::GetCurrentContext() && ImGui::GetIO().WantCaptureMouse)
        return;
    if (auto* pending = static_cast<PendingInput*>(glfwGetWindowUserPointer(window)))
        pending->scroll += y;
}

void onKey(GLFWwindow* window, int key, int /*scancode*/, int action, int /*mods*/)
{
    if (action != GLFW_PRESS || (ImGui::GetCurrentContext() && ImGui::GetIO().WantCaptureKeyboard))
        return;
    if (auto* pending = static_cast<PendingInput*>(glfwGetWindowUserPointer(window)))
        pending->pressed_keys.push_back(key);
}

// The window's default framebuffer, bottom row first as GL stores it, written top row first.
void writeScreenshot(const std::string& path, int width, int height)
{
    std::vector<uint8_t> rgb(size_t(width) * height * 3);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
    const size_t row = size_t(width) * 3;
    for (int y = 0; y < height / 2; ++y)
        std::swap_ranges(rgb.begin() + y * row, rgb.begin() + (y + 1) * row,
                         rgb.begin() + (height - 1 - y) * row);
    io::writePng(path, rgb.data(), width, height, 3);
}

// The viewer's per-session state and its frame.
class Viewer {
  public:
    // `start`: the camera the command line asked for (render's options), else the default.
    Viewer(gpu::WindowContext& window, render::TerrainRenderer& renderer, double fov_y_degrees,
           double epsilon_px, double texel_px, render::DebugMode mode, bool show_overlay,
           double exaggeration, const ResolvedCamera& start, const archive::ArchiveReader& reader,
           bool orbit)
        : window_(window), renderer_(renderer), fov_y_degrees_(fov_y_degrees),
          archive_(reader.path()), readout_(reader), show_overlay_(show_overlay)
    {
        settings_.epsilon_px = std::clamp(epsilon_px, kMinEpsilonPx, kMaxEpsilonPx);
        settings_.texel_px = texel_px; // range-checked by the option
        settings_.mode = mode;
        settings_.exaggeration = exaggeration;          // range-checked by the option
        settings_.scheme = renderer_.schemes().front(); // the first --lod, else the default

        int w = 1, h = 1;
        window_.framebufferSize(w, h);
        const lod::Viewport viewport{std::max(w, 1), std::max(h, 1)};
        render::HeadlessRenderOptions options; // the same camera `ridge render` would draw
        options.camera = start.position;
        options.look_at = start.look_at;
        options.fov_y_degrees = fov_y_degrees_;
        options.viewport = viewport;
        options.settings.exaggeration = settings_.exaggeration;
        fly_ = render::FlyCamera::from(render::cameraFor(renderer_, options));
        if (const lod::TerrainFrame& f = renderer_.quadtree().frame(); f.onEllipsoid())
            fly_.followEllipsoid(f.geodetic().ellipsoid); // true north, the local horizon
        // The speed follows the height above the ground (updateCamera), from the first frame.
        fly_.setSpeed(CameraReadout::flySpeed(heightAboveGround(), speed_rate_));
        if (orbit)
            toggleOrbit(); // run() refuses --orbit off a globe

        glfwSetWindowUserPointer(window_.window(), &pending_);
        glfwSetScrollCallback(window_.window(), onScroll);
        glfwSetKeyCallback(window_.window(), onKey);
        last_time_ = glfwGetTime();
    }
    ~Viewer() { glfwSetWindowUserPointer(window_.window(), nullptr); }
    Viewer(const Viewer&) = delete;
    Viewer& operator=(const Viewer&) = delete;

    bool quitRequested() const { return quit_ || window_.shouldClose(); }

    // Polls input, moves the camera, renders terrain and overlay into the back buffer.
    // Returns false (and draws nothing) while the framebuffer is empty (minimised window).
    bool frame()
    {
        window_.pollEvents();
        const double now = glfwGetTime();
        // A stalled frame (window drag, a slow synchronous patch load) must not teleport the
        // camera: cap the step at half a second.
        const double dt = std::clamp(now - last_time_, 0.0, 0.5);
        last_time_ = now;
        window_.framebufferSize(width_, height_);
        if (width_ <= 0 || height_ <= 0) {
            pending_ = {};
            glfwWaitEventsTimeout(0.1);
            return false;
        }
        handleKeys();
        updateCamera(dt);

        double near_m = 1.0, far_m = 1e6;
        renderer_.clipPlanesFor(fly_.position(), near_m, far_m, settings_.exaggeration);
        const lod::Camera camera =
            orbit_ ? orbit_->camera({width_, height_}, fov_y_degrees_, near_m, far_m)
                   : fly_.camera({width_, height_}, fov_y_degrees_, near_m, far_m);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glViewport(0, 0, width_, height_);
        stats_ = renderer_.draw(camera, settings_);

        // Smoothed over roughly the last 20 frames so the numbers are readable.
        const double frame_ms = dt * 1000.0;
        smoothed_ms_ =
            smoothed_ms_ <= 0.0 ? frame_ms : smoothed_ms_ + 0.05 * (frame_ms - smoothed_ms_);
        if (show_overlay_)
            drawOverlay(frame_ms);
        return true;
    }

    int width() const { return width_; }
    int height() const { return height_; }

  private:
    // P: the current camera as the `ridge render` command line that draws this view, on
    // stdout and the clipboard, and in the overlay until the next press.
    void printCamera()
    {
        camera_line_ = fmt::format(
            "ridge render {} -o view.png {} --fov {} --size {}x{}", shellQuoted(archive_),
            lod::renderCameraOptions(fly_.position(), fly_.yaw() * kDegreesPerRadian,
                                     fly_.pitch() * kDegreesPerRadian),
            formatNumber(fov_y_degrees_), width_, height_);
        fmt::print("{}\n", camera_line_);
        std::fflush(stdout);
        glfwSetClipboardString(window_.window(), camera_line_.c_str());
    }

    void handleKeys()
    {
        for (const int key : pending_.pressed_keys) {
            switch (key) {
            case GLFW_KEY_ESCAPE:
                quit_ = true;
                break;
            case GLFW_KEY_F1:
                settings_.mode = render::DebugMode::Shaded;
                break;
            case GLFW_KEY_F2:
                settings_.mode = render::DebugMode::LodLevels;
                break;
            case GLFW_KEY_F3:
                settings_.mode = render::DebugMode::TessellationFactors;
                break;
            case GLFW_KEY_F4:
            case GLFW_KEY_Z:
                settings_.wireframe = !settings_.wireframe;
                break;
            case GLFW_KEY_C:
                settings_.cull = !settings_.cull;
                break;
            case GLFW_KEY_K:
                settings_.skirts = !settings_.skirts;
                break;
            case GLFW_KEY_P:
                printCamera();
                break;
            case GLFW_KEY_G:
                settings_.fog = !settings_.fog;
                break;
            case GLFW_KEY_L: { // the next LOD scheme this renderer draws
                const std::vector<std::string>& names = renderer_.schemes();
                const auto at = std::find(names.begin(), names.end(), settings_.scheme);
                settings_.scheme =
                    at == names.end() || at + 1 == names.end() ? names.front() : *(at + 1);
                break;
            }
            case GLFW_KEY_H:
                clamp_to_ground_ = !clamp_to_ground_;
                break;
            case GLFW_KEY_M:
                if (renderer_.quadtree().frame().onEllipsoid())
                    toggleOrbit();
                break;
            case GLFW_KEY_O:
            case GLFW_KEY_F10:
                show_overlay_ = !show_overlay_;
                break;
            case GLFW_KEY_TAB:
                captured_ = !captured_;
                break;
            case GLFW_KEY_EQUAL: // '+' without Shift on US layouts
            case GLFW_KEY_KP_ADD:
                settings_.epsilon_px = std::min(settings_.epsilon_px * 1.25, kMaxEpsilonPx);
                break;
            case GLFW_KEY_MINUS:
            case GLFW_KEY_KP_SUBTRACT:
                settings_.epsilon_px = std::max(settings_.epsilon_px / 1.25, kMinEpsilonPx);
                break;
            default:
                break;
            }
        }
        pending_.pressed_keys.clear();
    }

    void updateCamera(double dt)
    {
        GLFWwindow* w = window_.window();
        const ImGuiIO& io = ImGui::GetIO();
        auto down = [&](int key) {
            return !io.WantCaptureKeyboard && glfwGetKey(w, key) == GLFW_PRESS;
        };
        render::FlyInput in;
        in.forward = down(GLFW_KEY_W);
        in.back = down(GLFW_KEY_S);
        in.left = down(GLFW_KEY_A);
        in.right = down(GLFW_KEY_D);
        in.up = down(GLFW_KEY_E) || down(GLFW_KEY_SPACE);
        in.down = down(GLFW_KEY_Q) || down(GLFW_KEY_LEFT_CONTROL);
        in.fast = down(GLFW_KEY_LEFT_SHIFT) || down(GLFW_KEY_RIGHT_SHIFT);
        // The wheel scales the speed's rate per metre of height; the speed itself follows the
        // height above the ground, so that skimming a valley is slow and crossing a continent
        // from orbit is not.
        // Orbiting, it zooms instead.
        const double zoom_steps = orbit_ ? pending_.scroll : 0.0;
        if (!orbit_)
            speed_rate_ = std::clamp(speed_rate_ * std::pow(fly_.speedFactor(), pending_.scroll),
                                     CameraReadout::kMinSpeedRate, CameraReadout::kMaxSpeedRate);
        pending_.scroll = 0.0;
        fly_.setSpeed(CameraReadout::flySpeed(heightAboveGround(), speed_rate_));

        // Mouse look while the right button is held (a press over the overlay belongs to the
        // overlay) or while Tab has captured the cursor. The cursor is hidden and unbounded
        // meanwhile, so a long drag never stops at the screen edge.
        const bool rmb = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
        if (!rmb)
            dragging_ = false;
        else if (!dragging_ && !io.WantCaptureMouse)
            dragging_ = true;
        const bool look = dragging_ || captured_;
        if (look != looking_) {
            glfwSetInputMode(w, GLFW_CURSOR, look ? GLFW_CURSOR_DISABLED : GLFW_CURSOR_NORMAL);
            looking_ = look;
            have_cursor_ = false; // the mode switch moves the reported position: no delta
        }
        if (looking_) {
            double x = 0.0, y = 0.0;
            glfwGetCursorPos(w, &x, &y);
            if (have_cursor_) {
                in.mouse_dx = x - cursor_x_;
                in.mouse_dy = y - cursor_y_;
            }
            cursor_x_ = x;
            cursor_y_ = y;
            have_cursor_ = true;
        }

        if (orbit_) {
            // Orbit: the mouse drags the Earth, the wheel and W/S zoom, A/D turn, E/Q tilt.
            render::OrbitInput orbit;
            orbit.drag_dx = in.mouse_dx;
            orbit.drag_dy = in.mouse_dy;
            orbit.zoom_steps = zoom_steps + 4.0 * dt * (double(in.forward) - double(in.back));
            orbit.turn = double(in.right) - double(in.left);
            orbit.tilt = double(in.up) - double(in.down);
            orbit_->update(orbit, {width_, height_}, fov_y_degrees_, dt);
            orbit_->setTargetHeight(
                renderer_.groundUnder(orbit_->target(), settings_.exaggeration));
            fly_.setPosition(orbit_->position()); // the overlay's readouts and clip planes
            return;
        }
        fly_.update(in, dt);
        // No tunnelling: never closer than 2 m above the drawn ground (along the local up).
        if (clamp_to_ground_)
            if (const double above = heightAboveGround(); above < 2.0)
                liftBy(2.0 - above);
    }

    // M: orbit the globe around the point in the middle of the view, or fly on from where the
    // orbit left the camera.
    void toggleOrbit()
    {
        const lod::Ellipsoid& e = renderer_.quadtree().frame().geodetic().ellipsoid;
        const lod::Viewport vp{std::max(width_, 1), std::max(height_, 1)};
        if (orbit_) {
            const lod::Camera c = orbit_->camera(vp, fov_y_degrees_, 1.0, 2.0);
            fly_ = render::FlyCamera::from(c, fly_.speed());
            fly_.followEllipsoid(e);
            orbit_.reset();
            return;
        }
        const lod::Camera c = fly_.camera(vp, fov_y_degrees_, 1.0, 2.0);
        const double ground = renderer_.groundUnder(c.position(), settings_.exaggeration);
        orbit_ = render::OrbitCamera::around(e, c, ground);
        orbit_->setTargetHeight(renderer_.groundUnder(orbit_->target(), settings_.exaggeration));
    }

    // Metres between the camera and the level-0 surface under it (negative below it), along
    // the local up: z on a plane, the height above the ellipsoid on a globe.
    double heightAboveGround() const
    {
        const glm::dvec3 p = fly_.position();
        const lod::TerrainFrame& frame = renderer_.quadtree().frame();
        if (frame.onEllipsoid())
            return frame.gridOf(p).z - renderer_.groundUnder(p, settings_.exaggeration);
        return p.z - renderer_.groundHeight(p.x, p.y, settings_.exaggeration);
    }

    // Moves the camera `metres` along the local up.
    void liftBy(double metres) { fly_.setPosition(fly_.position() + fly_.up() * metres); }

    // A compact panel in the top-left corner: frame rate, the camera in each of its frames and
    // the speed; statistics, settings and keys in sections that start closed. The title bar's
    // arrow collapses it to one line, O hides it.
    void drawOverlay(double frame_ms)
    {
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
        ImGui::SetNextWindowBgAlpha(0.6f);
        // Lines wrap at about a quarter of the window, so that no line widens the panel.
        const float wrap = std::clamp(0.28f * float(width_), 260.f, 380.f);
        ImGui::SetNextWindowSizeConstraints(ImVec2(0, 0), ImVec2(wrap + 24.f, float(height_)));
        char title[96];
        std::snprintf(title, sizeof title, "%.0f fps, %d patches###ridge view",
                      1000.0 / std::max(smoothed_ms_, 1e-3), stats_.patches);
        if (!ImGui::Begin(title, nullptr,
                          ImGuiWindowFlags_AlwaysAutoResize |
                              ImGuiWindowFlags_NoFocusOnAppearing)) {
            ImGui::End(); // collapsed: the title bar alone
            finishOverlay();
            return;
        }
        ImGui::PushTextWrapPos(wrap);
        const glm::dvec3 p = fly_.position();
        if (const lod::TerrainFrame& f = renderer_.quadtree().frame(); f.onEllipsoid()) {
            // ECEF, and WGS 84 longitude, latitude and height above the ellipsoid.
            const lod::Geodetic g = lod::ecefToGeodetic(f.geodetic().ellipsoid, p);
            ImGui::Text("ECEF: x %.1f, y %.1f, z %.1f m", p.x, p.y, p.z);
            ImGui::Text("WGS 84: %.6f°, %.6f°, %.1f m above the ellipsoid",
                        g.longitude * kDegreesPerRadian, g.latitude * kDegreesPerRadian, g.height);
        } else {
            for (const std::string& line : readout_.positionLines(p))
                ImGui::TextUnformatted(line.c_str());
        }
        if (orbit_)
            ImGui::Text("orbiting %.4f°, %.4f° from %.0f m, heading %.1f°, tilt %.1f° (M: fly)",
                        orbit_->longitude() * kDegreesPerRadian,
                        orbit_->latitude() * kDegreesPerRadian, orbit_->range(),
                        orbit_->heading() * kDegreesPerRadian, orbit_->tilt() * kDegreesPerRadian);
        ImGui::Text("%.0f m above ground, speed %.0f m/s", heightAboveGround(), fly_.speed());
        ImGui::Text("heading %.1f° from %s north, pitch %.1f°", fly_.yaw() * kDegreesPerRadian,
                    fly_.onEllipsoid() ? "true" : "grid", fly_.pitch() * kDegreesPerRadian);
        if (stats_.missing > 0)
            ImGui::Text("streaming: %d patches to come", stats_.missing);
        const std::string stream_error = renderer_.streamingError();
        if (!stream_error.empty())
            ImGui::TextColored(ImVec4(1.f, 0.4f, 0.3f, 1.f), "%s", stream_error.c_str());
        if (stats_.epsilon_px > settings_.epsilon_px * 1.0001)
            ImGui::TextColored(ImVec4(1.f, 0.7f, 0.3f, 1.f),
                               "epsilon raised to %.2f px: the selection exceeded the slots",
                               stats_.epsilon_px);
        if (!camera_line_.empty())
            ImGui::TextWrapped("copied: %s", camera_line_.c_str());
        drawLegend();
        if (ImGui::CollapsingHeader("statistics")) {
            ImGui::Text("%.2f ms smoothed, this frame %.2f ms", smoothed_ms_, frame_ms);
            ImGui::Text("GPU terrain %.2f ms, uploads %.2f ms", stats_.gpu_ms,
                        stats_.gpu_upload_ms);
            ImGui::Text("triangles %.3f M (%.1f Mtri/s)", double(stats_.triangles) * 1e-6,
                        double(stats_.triangles) * 1e-3 / std::max(smoothed_ms_, 1e-3));
            ImGui::Text("CPU select %.2f ms, load %.2f ms", stats_.cpu_select_ms,
                        stats_.cpu_load_ms);
            ImGui::Text("patches: %d drawn, %d culled, %d resident, %d loaded", stats_.patches,
                        stats_.culled, stats_.resident, stats_.loaded);
            ImGui::Text("read %.1f kB, decoded %.1f kB, uploaded %.1f kB (%d on the GPU)",
                        double(stats_.bytes_read) / 1024.0, double(stats_.bytes_decoded) / 1024.0,
                        double(stats_.bytes_uploaded) / 1024.0, stats_.reconstructed);
            if (stats_.levels > 0) // level windows (clipmaps)
                ImGui::Text("levels: %d drawn of %d wanted, %d deactivated by height; %d "
                            "shifted, %.1f k samples written",
                            stats_.levels_drawn, stats_.levels_wanted,
                            stats_.levels - stats_.levels_wanted, stats_.level_shifts,
                            double(stats_.samples_written) * 1e-3);
            ImGui::Text("GL: %s", window_.rendererName().c_str());
        }
        if (ImGui::CollapsingHeader("settings")) {
            float epsilon = float(settings_.epsilon_px);
            if (ImGui::SliderFloat("epsilon (px)", &epsilon, float(kMinEpsilonPx),
                                   float(kMaxEpsilonPx), "%.2f", ImGuiSliderFlags_Logarithmic))
                settings_.epsilon_px = std::clamp(double(epsilon), kMinEpsilonPx, kMaxEpsilonPx);
            float texel = float(settings_.texel_px);
            if (ImGui::SliderFloat("texel size (px, 0 off)", &texel, 0.f, 16.f, "%.2f"))
                settings_.texel_px = std::clamp(double(texel), 0.0, 16.0);
            // Vertical exaggeration: the camera keeps its height above the drawn ground.
            float k = float(settings_.exaggeration);
            if (ImGui::SliderFloat("vertical exaggeration", &k, 0.1f, 20.f, "%.2f",
                                   ImGuiSliderFlags_Logarithmic)) {
                const double above = heightAboveGround();
                settings_.exaggeration = std::clamp(double(k), 0.1, 20.0);
                liftBy(above - heightAboveGround());
            }
            float rate = float(speed_rate_);
            if (ImGui::SliderFloat(
                    "speed (x height / s)", &rate, float(CameraReadout::kMinSpeedRate),
                    float(CameraReadout::kMaxSpeedRate), "%.2f", ImGuiSliderFlags_Logarithmic))
                speed_rate_ = std::clamp(double(rate), CameraReadout::kMinSpeedRate,
                                         CameraReadout::kMaxSpeedRate);
            int mode = int(settings_.mode);
            if (ImGui::Combo("mode", &mode, "shaded\0LOD levels\0tessellation factors\0"))
                settings_.mode = render::DebugMode(mode);
            ImGui::Checkbox("wireframe", &settings_.wireframe);
            ImGui::SameLine();
            ImGui::Checkbox("cull", &settings_.cull);
            ImGui::SameLine();
            ImGui::Checkbox("skirts", &settings_.skirts);
            ImGui::SameLine();
            ImGui::Checkbox("fog", &settings_.fog);
            ImGui::Checkbox("stay above ground", &clamp_to_ground_);
            ImGui::Text("LOD scheme: %s (L: next)", settings_.scheme.c_str());
        }
        if (ImGui::CollapsingHeader("keys")) {
            ImGui::TextUnformatted("WASD move, Q/E down/up, Shift fast, wheel speed, right-drag "
                                   "or Tab look");
            ImGui::TextUnformatted("M orbit the globe: right-drag or Tab turns the Earth, wheel "
                                   "or W/S zoom, A/D heading, E/Q tilt");
            ImGui::TextUnformatted("F1-F3 modes, F4/Z wireframe, C cull, K skirts, L scheme, G "
                                   "fog, H ground, O overlay, +/- epsilon, P print/copy camera, "
                                   "Esc quit");
        }
        ImGui::PopTextWrapPos();
        ImGui::End();
        finishOverlay();
    }

    static void finishOverlay()
    {
        ImGui::Render();
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    }

    // The debug modes' colour keys, from the palette the shader is given
    // (render::legendEntries).
    void drawLegend() const
    {
        const std::vector<render::LegendEntry> entries = render::legendEntries(
            settings_.mode, renderer_.quadtree().geometry().finestLevel(), renderer_.blockCells());
        if (entries.empty())
            return;
        ImGui::TextUnformatted(settings_.mode == render::DebugMode::LodLevels
                                   ? "legend: quadtree level"
                                   : "legend: tessellation factor (segments per block edge)");
        for (size_t k = 0; k < entries.size(); ++k) {
            const render::LegendEntry& e = entries[k];
            if (k % 8 != 0)
                ImGui::SameLine();
            ImGui::ColorButton(e.label.c_str(), ImVec4(e.colour.r, e.colour.g, e.colour.b, 1.f),
                               ImGuiColorEditFlags_NoTooltip, ImVec2(14.f, 14.f));
            ImGui::SameLine();
            ImGui::Text("%s", e.label.c_str());
        }
    }

    gpu::WindowContext& window_;
    render::TerrainRenderer& renderer_;
    double fov_y_degrees_;
    std::string archive_;
    std::string camera_line_; // the last camera P printed
    CameraReadout readout_;
    render::RenderSettings settings_;
    render::FlyCamera fly_;
    std::optional<render::OrbitCamera> orbit_; // M on a globe: orbiting instead of flying
    render::FrameStats stats_;
    PendingInput pending_;
    bool quit_ = false;
    bool clamp_to_ground_ = true;
    bool show_overlay_ = true; // O or F10
    // Fly speed per metre of height above the ground, per second (the wheel scales it).
    double speed_rate_ = CameraReadout::kDefaultSpeedRate;
    bool captured_ = false; // Tab: mouse look without holding a button
    bool dragging_ = false; // right button held, pressed outside the overlay
    bool looking_ = false;  // cursor disabled for mouse look
    bool have_cursor_ = false;
    double cursor_x_ = 0.0, cursor_y_ = 0.0; // screen coordinates, last frame
    double last_time_ = 0.0;                 // seconds, glfwGetTime
    double smoothed_ms_ = 0.0;
    int width_ = 0, height_ = 0; // framebuffer pixels
};

#endif // RIDGE_HAVE_VIEWER

} // namespace

void ViewCommand::registerWith(CLI::App& app)
{
    command_ = app.add_subcommand(
        "view", "Fly over an archive in a window (hardware-tessellation renderer, stats overlay)");
    command_->add_option("archive", archive_, "Archive (.ridge)")->required();
    command_->add_option("--size", size_, "Window size WIDTHxHEIGHT in screen coordinates")
        ->capture_default_str();
    command_->add_option("--fov", fov_y_degrees_, "Vertical field of view, degrees")
        ->capture_default_str()
        ->check(inRange("--fov", render::HeadlessRenderOptions::kFovYDegreesRange));
    command_->add_option("--error", epsilon_px_, "Screen-space error threshold ε, pixels")
        ->capture_default_str()
        ->check(inRange("--error", ValueRange::closed(kMinEpsilonPx, kMaxEpsilonPx)));
    addCameraOptions(*command_, camera_args_, "an oblique view of the whole terrain");
    addModeOption(*command_, mode_);
    command_->add_flag("--no-overlay", no_overlay_,
                       "Start with the statistics overlay hidden (O or F10 shows it)");
    addTexelSizeOption(*command_, texel_px_);
    addExaggerationOption(*command_, exaggeration_);
    addStreamingOptions(*command_, renderer_options_);
    command_
        ->add_option("--lod", lod_,
                     lodSchemeHelp() +
                         "\nRepeat it for each scheme L cycles through, the first drawn first "
                         "(default: every scheme that needs no decoding on the CPU, with its "
                         "default options)")
        ->check(lodSpecCheck("--lod"));
    command_->add_flag("--vsync,!--no-vsync", vsync_,
                       "Wait for the display's refresh (default on)");
    command_
        ->add_option("--frames", frames_, "Render this many frames, then exit (0 = until closed)")
        ->check(inIntegerRange("--frames", 0, lod::CameraPathSettings::kMaxFrames));
    // For scripts, docs and bug reports: the last frame, overlay included. Hidden (empty group)
    // to keep the user-facing help short.
    command_->add_option("--screenshot", screenshot_, "Write the last frame as a PNG")->group("");
    addFrameOption(*command_, frame_);
    command_->add_flag("--orbit", orbit_,
                       "Start orbiting the globe around the point in the middle of the view "
                       "(M switches between orbit and fly)");
}

int ViewCommand::run()
{
    const lod::Viewport size = parseSize(size_);
    renderer_options_.schemes = lod_;
    renderer_options_.frame = parseFrameChoice(frame_);
    try {
        renderer_options_.validate(); // each --lod checked already; a scheme given twice
    } catch (const Error& e) {
        throw UsageError(std::string("--lod: ") + e.what());
    }
    const int width = size.width, height = size.height;
#if !RIDGE_HAVE_VIEWER
    throw Error("ridge view: this ridge was built without the viewer (Dear ImGui or its "
                "GLFW/OpenGL3 backend sources were missing at configure time); use `ridge render` "
                "for images");
#else
    // Checked up front: GLFW's own message for this ("X11: The DISPLAY environment variable is
    // missing") does not say what to do instead.
    const char* display = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    if ((!display || !*display) && (!wayland || !*wayland))
        throw Error("ridge view: cannot open a window: no display (DISPLAY is not set); use "
                    "`ridge render` for headless output");
    const archive::ArchiveReader reader(archive_);
    // Before the window: a bad camera is an error, not a flash of a window (nor, under
    // LeakSanitizer, an exit after the GL driver is unloaded, whose leftovers it cannot name).
    // In the frame the renderer will draw in (ECEF on the globe), as `ridge render` does.
    const lod::TerrainFrame frame = lod::terrainFrameOf(reader, renderer_options_.frame, archive_);
    if (orbit_ && !frame.onEllipsoid())
        throw UsageError("--orbit: " + archive_ +
                         " is drawn on a plane; orbiting needs the globe (--frame ellipsoid)");
    ResolvedCamera start;
    if (CameraPlacement placement = camera_args_.placement(); !placement.empty()) {
        HeightQuery query(archive_);
        placement.exaggeration = exaggeration_;
        start = resolveCameraPlacement(query, placement, &frame);
    }
    std::unique_ptr<gpu::WindowContext> window;
    try {
        window =
            std::make_unique<gpu::WindowContext>(width, height, "ridge view: " + archive_, vsync_);
    } catch (const Error& e) {
        throw Error(
            fmt::format("ridge view: {}; use `ridge render` for headless output", e.what()));
    }
    {
        // Declaration order is destruction order in reverse: the overlay and the renderer
        // release their GL objects while the window's context is still alive.
        // Streaming: the window never waits for disk or decoding; missing patches are drawn by
        // their resident ancestors until they arrive.
        render::TerrainRenderer renderer(reader, renderer_options_);
        Viewer viewer(*window, renderer, fov_y_degrees_, epsilon_px_, texel_px_,
                      parseDebugMode(mode_), !no_overlay_, exaggeration_, start, reader, orbit_);
        const ImGuiSession imgui(window->window());

        for (int frame = 0; frames_ == 0 || frame < frames_; ++frame) {
            if (interrupted())
                throw Cancelled();
            if (viewer.quitRequested())
                break;
            const bool drawn = viewer.frame();
            const bool last = frames_ > 0 && frame + 1 == frames_;
            if (drawn && last && !screenshot_.empty()) {
                writeScreenshot(screenshot_, viewer.width(), viewer.height());
                screenshot_.clear();
            }
            if (drawn)
                window->swapBuffers();
        }
        // Closed by the user (or minimised at the last frame): one more frame for the shot.
        if (!screenshot_.empty()) {
            if (!viewer.frame())
                throw Error(fmt::format(
                    "{}: cannot take a screenshot of an empty (minimised) window", screenshot_));
            writeScreenshot(screenshot_, viewer.width(), viewer.height());
        }
    }
#if RIDGE_ADDRESS_SANITIZER
    // The window's destructor (glfwTerminate, XCloseDisplay) unloads Mesa's DRI driver; LSan's
    // exit-time check then cannot name the driver's own leftovers, so no suppression in
    // scripts/lsan.supp can match them. Check now, with every ridge object of the viewer gone
    // and the driver still loaded (the exit-time check is then skipped).
    __lsan_do_leak_check();
#endif
    return 0;
#endif
}

} // namespace ridge::cli
