// The window of `svo view`: GLFW (no client API) with a Vulkan surface, and
// the mouse and keyboard input gathered between two frames. Only
// view_window.cpp includes GLFW; the viewer sees Input.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "svo/render/vk_context.h"

struct GLFWwindow;

namespace svo::tools {

// What happened since the last poll. Drags are in window pixels (x right, y down).
struct Input {
  double rotate_x = 0, rotate_y = 0;  // left-button drag
  double pan_x = 0, pan_y = 0;        // right- or middle-button drag
  double scroll = 0;                  // wheel steps, positive away from the user
  std::vector<uint32_t> keys;         // see Window::Key, in the order pressed
  bool resized = false;               // the framebuffer changed size
  bool exposed = false;               // the window system asks for the picture again
  double cursor_x = 0, cursor_y = 0;  // last cursor position, window pixels
};

class Window {
 public:
  // Layout-independent key codes delivered in Input::keys.
  enum Key : uint32_t {
    kQuit = 1,  // Esc, Q, or closing the window
    kZoomIn,    // + (or =, keypad +)
    kZoomOut,   // - (keypad -)
    kMode1,
    kMode2,
    kMode3,
    kMode4,
    kShadows,     // S
    kReset,       // R
    kFocus,       // F
    kScreenshot,  // P or F12
    kHelp,        // H or F1
  };

  // Whether a window can be opened at all (GLFW initialises: a display, a
  // Vulkan loader with surface support), without opening one, so that long
  // work before the window (voxelizing a mesh) is not done in vain.
  // @throw std::runtime_error as the constructor.
  static void check_display();

  // Opens a window of width x height screen coordinates.
  // @throw std::runtime_error "cannot open a window: <GLFW's reason> (...)"
  //        when there is no display, or GLFW finds no Vulkan loader.
  Window(const std::string& title, int width, int height);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  // Adds what presenting to this window needs to `options`: GLFW's instance
  // extensions and a create_surface callback. The window must outlive the Context.
  void prepare(vk::ContextOptions& options);

  // Processes window events and returns the input gathered since the last
  // call; with `wait` blocks until at least one event arrives.
  Input poll(bool wait);
  // The same, blocking at most `seconds` (> 0) for the first event.
  Input poll_for(double seconds);

  bool closing() const;
  void set_title(const std::string& title);
  // Framebuffer size in pixels (0 x 0 while minimised).
  void framebuffer_size(uint32_t& width, uint32_t& height) const;
  // Size in screen coordinates (the unit of Input's drags).
  void window_size(uint32_t& width, uint32_t& height) const;

 private:
  Input take_input();  // what gathered since the last call

  GLFWwindow* window_ = nullptr;
  Input pending_;
  double last_x_ = 0, last_y_ = 0;  // cursor position at the previous event
};

}  // namespace svo::tools
