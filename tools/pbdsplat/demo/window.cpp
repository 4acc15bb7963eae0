#include "demo/window.h"

#include <cstdlib>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

namespace pbdsplat::demo {

struct WindowCallbacks {
    static Window& of(GLFWwindow* w) { return *static_cast<Window*>(glfwGetWindowUserPointer(w)); }
    static Vec2f cursor(GLFWwindow* w) {
        double x = 0, y = 0;
        glfwGetCursorPos(w, &x, &y);
        return {float(x), float(y)};
    }
    static void button(GLFWwindow* w, int button, int action, int mods) {
        const int b = button == GLFW_MOUSE_BUTTON_LEFT ? 0 : button == GLFW_MOUSE_BUTTON_RIGHT ? 1 : 2;
        InputEvent e;
        e.kind = action == GLFW_PRESS ? InputEvent::Kind::press : InputEvent::Kind::release;
        e.button = b;
        e.position = cursor(w);
        e.shift = (mods & GLFW_MOD_SHIFT) != 0;
        of(w).events_.push_back(e);
    }
    static void move(GLFWwindow* w, double x, double y) {
        InputEvent e;
        e.kind = InputEvent::Kind::move;
        e.position = {float(x), float(y)};
        of(w).events_.push_back(e);
    }
    static void scroll(GLFWwindow* w, double, double dy) {
        InputEvent e;
        e.kind = InputEvent::Kind::scroll;
        e.scroll = float(dy);
        of(w).events_.push_back(e);
    }
    static void key(GLFWwindow* w, int key, int, int action, int mods) {
        if (action == GLFW_RELEASE) return;
        InputEvent e;
        e.kind = InputEvent::Kind::key;
        e.shift = (mods & GLFW_MOD_SHIFT) != 0;
        if ((key >= GLFW_KEY_A && key <= GLFW_KEY_Z) || (key >= GLFW_KEY_0 && key <= GLFW_KEY_9)) e.key = key;  // ASCII
        else if (key == GLFW_KEY_SPACE) e.key = key_space;
        else if (key == GLFW_KEY_ESCAPE) e.key = key_escape;
        else if (key == GLFW_KEY_F1) e.key = key_f1;
        else if (key == GLFW_KEY_UP) e.key = key_up;
        else if (key == GLFW_KEY_DOWN) e.key = key_down;
        else if (key == GLFW_KEY_TAB) e.key = key_tab;
        else if (key == GLFW_KEY_EQUAL || key == GLFW_KEY_KP_ADD) e.key = key_plus;
        else if (key == GLFW_KEY_MINUS || key == GLFW_KEY_KP_SUBTRACT) e.key = key_minus;
        else return;
        of(w).events_.push_back(e);
    }
};

namespace {
std::string glfw_error() {
    const char* description = nullptr;
    glfwGetError(&description);
    return description ? description : "unknown GLFW error";
}
} // namespace

core::Result<std::unique_ptr<Window>> Window::create(const std::string& title, uint32_t width, uint32_t height) {
    const char* x11 = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    if ((!x11 || !*x11) && (!wayland || !*wayland))
        return core::make_error("no display to open a window on (DISPLAY and WAYLAND_DISPLAY are unset); "
                                "render offscreen with 'pbdsplat render', or run under Xvfb (xvfb-run -a pbdsplat run ...)");
    if (!glfwInit()) return core::make_error("cannot open the display: " + glfw_error() + "; render offscreen with 'pbdsplat render'");
    if (!glfwVulkanSupported()) {
        glfwTerminate();
        return core::make_error("GLFW finds no Vulkan loader to draw into a window with");
    }
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    auto w = std::unique_ptr<Window>(new Window());
    w->window_ = glfwCreateWindow(int(width), int(height), title.c_str(), nullptr, nullptr);
    if (!w->window_) {
        const std::string why = glfw_error();
        glfwTerminate();
        return core::make_error("cannot create a " + std::to_string(width) + "x" + std::to_string(height) + " window: " + why);
    }
    glfwSetWindowUserPointer(w->window_, w.get());
    glfwSetMouseButtonCallback(w->window_, WindowCallbacks::button);
    glfwSetCursorPosCallback(w->window_, WindowCallbacks::move);
    glfwSetScrollCallback(w->window_, WindowCallbacks::scroll);
    glfwSetKeyCallback(w->window_, WindowCallbacks::key);
    return w;
}

Window::~Window() {
    if (window_) glfwDestroyWindow(window_);
    glfwTerminate();
}

std::vector<std::string> Window::required_extensions() {
    uint32_t n = 0;
    const char** names = glfwGetRequiredInstanceExtensions(&n);
    return std::vector<std::string>(names, names + n);
}

core::Result<VkSurfaceKHR> Window::create_surface(VkInstance instance) {
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    const VkResult r = glfwCreateWindowSurface(instance, window_, nullptr, &surface);
    if (r != VK_SUCCESS) return core::make_error(std::string("cannot make a Vulkan surface for the window: ") + gpu::vk_result_name(r));
    return surface;
}

std::vector<InputEvent> Window::poll() {
    glfwPollEvents();
    return std::exchange(events_, {});
}

void Window::wait() { glfwWaitEventsTimeout(0.1); }
bool Window::should_close() const { return glfwWindowShouldClose(window_); }
void Window::request_close() { glfwSetWindowShouldClose(window_, GLFW_TRUE); }

VkExtent2D Window::framebuffer_size() const {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    return {uint32_t(std::max(w, 0)), uint32_t(std::max(h, 0))};
}

Vec2f Window::cursor() const { return WindowCallbacks::cursor(window_); }
void Window::set_title(const std::string& title) { glfwSetWindowTitle(window_, title.c_str()); }

} // namespace pbdsplat::demo
