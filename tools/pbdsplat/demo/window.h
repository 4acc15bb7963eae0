#pragma once
// The demo's window (GLFW, no client API: Vulkan draws into it) and the input it collects.
#include <memory>
#include <string>
#include <vector>

#include "core/math.h"
#include "core/result.h"
#include "gpu/vk.h"

struct GLFWwindow;

namespace pbdsplat::demo {

// One input event, in window pixels (y down). Scripts produce the same events.
struct InputEvent {
    enum class Kind { press, release, move, scroll, key } kind = Kind::move;
    int button = 0;          // 0 left, 1 right, 2 middle (press, release)
    Vec2f position{0, 0};    // press, release, move
    float scroll = 0.0f;     // scroll: lines, up positive
    int key = 0;             // key: an upper-case letter, a digit, or one of the Key values
    bool shift = false;
};
enum Key : int { key_space = ' ', key_escape = 256, key_f1, key_up, key_down, key_tab, key_plus = '+', key_minus = '-' };

class Window {
public:
    // Fails with a clear reason where there is no display (and says what to use instead).
    static core::Result<std::unique_ptr<Window>> create(const std::string& title, uint32_t width, uint32_t height);
    ~Window();

    // Instance extensions the window system needs, and the surface once there is an instance.
    static std::vector<std::string> required_extensions();
    core::Result<VkSurfaceKHR> create_surface(VkInstance instance);

    // Collects the events since the last call (does not block).
    std::vector<InputEvent> poll();
    // Blocks until something happens (while minimised).
    void wait();
    bool should_close() const;
    void request_close();
    VkExtent2D framebuffer_size() const;
    Vec2f cursor() const;
    void set_title(const std::string& title);

private:
    Window() = default;
    GLFWwindow* window_ = nullptr;
    std::vector<InputEvent> events_;
    friend struct WindowCallbacks;
};

} // namespace pbdsplat::demo
