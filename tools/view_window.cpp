#include "view_window.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <algorithm>
#include <stdexcept>

namespace svo::tools {

namespace {

std::string g_glfw_error;  // GLFW reports failures through a callback; the latest is kept here

void on_error(int, const char* description) { g_glfw_error = description ? description : "unknown error"; }

Window* self(GLFWwindow* w) { return static_cast<Window*>(glfwGetWindowUserPointer(w)); }

// glfwInit and the Vulkan loader's presence; GLFW stays initialised on success.
void init_glfw() {
  glfwSetErrorCallback(on_error);
  if (!glfwInit()) {
    throw std::runtime_error("cannot open a window: " + g_glfw_error +
                             " (no display: set DISPLAY, or run under xvfb-run)");
  }
  if (!glfwVulkanSupported()) {
    glfwTerminate();
    throw std::runtime_error("cannot open a window: GLFW finds no Vulkan loader with surface support (" + g_glfw_error +
                             ")");
  }
}

}  // namespace

void Window::check_display() {
  init_glfw();
  glfwTerminate();
}

Window::Window(const std::string& title, int width, int height) {
  init_glfw();
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!window_) {
    glfwTerminate();
    throw std::runtime_error("cannot open a window: " + g_glfw_error);
  }
  glfwSetWindowUserPointer(window_, this);
  glfwGetCursorPos(window_, &last_x_, &last_y_);
  pending_.cursor_x = last_x_;
  pending_.cursor_y = last_y_;

  glfwSetCursorPosCallback(window_, [](GLFWwindow* w, double x, double y) {
    Window& me = *self(w);
    double dx = x - me.last_x_, dy = y - me.last_y_;
    me.last_x_ = x;
    me.last_y_ = y;
    me.pending_.cursor_x = x;
    me.pending_.cursor_y = y;
    if (glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS) {
      me.pending_.rotate_x += dx;
      me.pending_.rotate_y += dy;
    } else if (glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS ||
               glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS) {
      me.pending_.pan_x += dx;
      me.pending_.pan_y += dy;
    }
  });
  glfwSetScrollCallback(window_, [](GLFWwindow* w, double, double y) { self(w)->pending_.scroll += y; });
  glfwSetFramebufferSizeCallback(window_, [](GLFWwindow* w, int, int) { self(w)->pending_.resized = true; });
  glfwSetWindowRefreshCallback(window_, [](GLFWwindow* w) { self(w)->pending_.exposed = true; });
  glfwSetWindowCloseCallback(window_, [](GLFWwindow* w) { self(w)->pending_.keys.push_back(kQuit); });
  // '+' and '-' by character, so that they work on any keyboard layout.
  glfwSetCharCallback(window_, [](GLFWwindow* w, unsigned int c) {
    if (c == '+' || c == '=') self(w)->pending_.keys.push_back(kZoomIn);
    if (c == '-') self(w)->pending_.keys.push_back(kZoomOut);
  });
  glfwSetKeyCallback(window_, [](GLFWwindow* w, int key, int, int action, int) {
    if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
    std::vector<uint32_t>& keys = self(w)->pending_.keys;
    switch (key) {
      case GLFW_KEY_ESCAPE:
      case GLFW_KEY_Q:
        keys.push_back(kQuit);
        break;
      case GLFW_KEY_KP_ADD:
        keys.push_back(kZoomIn);
        break;
      case GLFW_KEY_KP_SUBTRACT:
        keys.push_back(kZoomOut);
        break;
      case GLFW_KEY_1:
        keys.push_back(kMode1);
        break;
      case GLFW_KEY_2:
        keys.push_back(kMode2);
        break;
      case GLFW_KEY_3:
        keys.push_back(kMode3);
        break;
      case GLFW_KEY_4:
        keys.push_back(kMode4);
        break;
      case GLFW_KEY_S:
        if (action == GLFW_PRESS) keys.push_back(kShadows);
        break;
      case GLFW_KEY_R:
        keys.push_back(kReset);
        break;
      case GLFW_KEY_F:
        keys.push_back(kFocus);
        break;
      case GLFW_KEY_P:
      case GLFW_KEY_F12:
        if (action == GLFW_PRESS) keys.push_back(kScreenshot);
        break;
      case GLFW_KEY_H:
      case GLFW_KEY_F1:
        if (action == GLFW_PRESS) keys.push_back(kHelp);
        break;
      default:
        break;
    }
  });
}

Window::~Window() {
  if (window_) glfwDestroyWindow(window_);
  glfwTerminate();
}

void Window::prepare(vk::ContextOptions& options) {
  uint32_t count = 0;
  const char** names = glfwGetRequiredInstanceExtensions(&count);
  if (!names) throw std::runtime_error("cannot present: GLFW knows no Vulkan surface extension for this display");
  for (uint32_t i = 0; i < count; ++i) options.instance_extensions.emplace_back(names[i]);
  GLFWwindow* window = window_;
  options.create_surface = [window](VkInstance instance) {
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    SVO_VK_CHECK(glfwCreateWindowSurface(instance, window, nullptr, &surface));
    return surface;
  };
}

Input Window::poll(bool wait) {
  if (wait) {
    glfwWaitEvents();
  } else {
    glfwPollEvents();
  }
  return take_input();
}

Input Window::poll_for(double seconds) {
  glfwWaitEventsTimeout(seconds);
  return take_input();
}

Input Window::take_input() {
  Input input = pending_;
  pending_ = Input{};
  pending_.cursor_x = input.cursor_x;
  pending_.cursor_y = input.cursor_y;
  return input;
}

bool Window::closing() const { return glfwWindowShouldClose(window_); }

void Window::set_title(const std::string& title) { glfwSetWindowTitle(window_, title.c_str()); }

void Window::framebuffer_size(uint32_t& width, uint32_t& height) const {
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_, &w, &h);
  width = uint32_t(std::max(w, 0));
  height = uint32_t(std::max(h, 0));
}

void Window::window_size(uint32_t& width, uint32_t& height) const {
  int w = 0, h = 0;
  glfwGetWindowSize(window_, &w, &h);
  width = uint32_t(std::max(w, 0));
  height = uint32_t(std::max(h, 0));
}

}  // namespace svo::tools
