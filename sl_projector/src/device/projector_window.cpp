#include "device/projector_window.h"

#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include <X11/Xlib.h>
#include <X11/Xutil.h>

namespace sl_projector
{

struct ProjectorWindow::Impl
{
  Display* display = nullptr;
  Window window = 0;
  GC gc = nullptr;
  XImage* image = nullptr;  // owns pixels (allocated with malloc, freed by XDestroyImage)
  int width = 0;
  int height = 0;

  void destroyImage()
  {
    if (image)
      XDestroyImage(image);
    image = nullptr;
  }

  void setFrame(const cv::Mat& frame)
  {
    if (frame.empty() || frame.type() != CV_8UC1)
      throw std::invalid_argument("ProjectorWindow: frame must be a non-empty mono8 (CV_8UC1) image");
    const int screen = DefaultScreen(display);
    Visual* visual = DefaultVisual(display, screen);
    const int depth = DefaultDepth(display, screen);
    if (depth != 24 && depth != 32)
      throw std::runtime_error("ProjectorWindow: X visual depth " + std::to_string(depth) +
                               " is not supported (need 24 or 32 bit TrueColor)");
    destroyImage();
    char* pixels = static_cast<char*>(std::malloc(static_cast<size_t>(frame.cols) * frame.rows * 4));
    if (!pixels)
      throw std::runtime_error("ProjectorWindow: out of memory");
    image = XCreateImage(display, visual, static_cast<unsigned>(depth), ZPixmap, 0, pixels,
                         static_cast<unsigned>(frame.cols), static_cast<unsigned>(frame.rows), 32, 0);
    if (!image)
    {
      std::free(pixels);
      throw std::runtime_error("ProjectorWindow: XCreateImage failed");
    }
    for (int y = 0; y < frame.rows; ++y)
    {
      const uint8_t* src = frame.ptr<uint8_t>(y);
      for (int x = 0; x < frame.cols; ++x)
      {
        const unsigned long g = src[x];
        XPutPixel(image, x, y, (g << 16) | (g << 8) | g);
      }
    }
    width = frame.cols;
    height = frame.rows;
  }

  void draw()
  {
    if (display && window && image)
    {
      XPutImage(display, window, gc, image, 0, 0, 0, 0, static_cast<unsigned>(width), static_cast<unsigned>(height));
      XFlush(display);
    }
  }
};

ProjectorWindow::ProjectorWindow() : impl_(new Impl) {}

ProjectorWindow::~ProjectorWindow()
{
  close();
}

void ProjectorWindow::open(const std::string& display_name, int x, int y, const cv::Mat& frame)
{
  close();
  Impl& d = *impl_;
  d.display = XOpenDisplay(display_name.empty() ? nullptr : display_name.c_str());
  if (!d.display)
    throw std::runtime_error("ProjectorWindow: cannot open X display '" +
                             (display_name.empty() ? std::string("$DISPLAY") : display_name) +
                             "' (is X running there and may this user connect?)");
  try
  {
    d.setFrame(frame);
  }
  catch (...)
  {
    close();
    throw;
  }
  const int screen = DefaultScreen(d.display);
  XSetWindowAttributes attributes;
  std::memset(&attributes, 0, sizeof(attributes));
  attributes.override_redirect = True;  // no decorations, no window-manager placement
  attributes.background_pixel = BlackPixel(d.display, screen);
  attributes.event_mask = ExposureMask;
  d.window = XCreateWindow(d.display, RootWindow(d.display, screen), x, y, static_cast<unsigned>(d.width),
                           static_cast<unsigned>(d.height), 0, CopyFromParent, InputOutput, CopyFromParent,
                           CWOverrideRedirect | CWBackPixel | CWEventMask, &attributes);
  XStoreName(d.display, d.window, "sl_projector pattern");
  d.gc = XCreateGC(d.display, d.window, 0, nullptr);
  XMapRaised(d.display, d.window);
  XSync(d.display, False);
  d.draw();
}

void ProjectorWindow::show(const cv::Mat& frame)
{
  if (!isOpen())
    throw std::runtime_error("ProjectorWindow: show() before open()");
  impl_->setFrame(frame);
  XResizeWindow(impl_->display, impl_->window, static_cast<unsigned>(impl_->width),
                static_cast<unsigned>(impl_->height));
  impl_->draw();
}

void ProjectorWindow::spinOnce()
{
  Impl& d = *impl_;
  if (!d.display)
    return;
  bool exposed = false;
  while (XPending(d.display) > 0)
  {
    XEvent event;
    XNextEvent(d.display, &event);
    exposed = exposed || event.type == Expose;
  }
  if (exposed)
    d.draw();
}

bool ProjectorWindow::isOpen() const
{
  return impl_->display != nullptr && impl_->window != 0;
}

void ProjectorWindow::close()
{
  Impl& d = *impl_;
  d.destroyImage();
  if (d.display)
  {
    if (d.gc)
      XFreeGC(d.display, d.gc);
    if (d.window)
      XDestroyWindow(d.display, d.window);
    XCloseDisplay(d.display);
  }
  d.display = nullptr;
  d.window = 0;
  d.gc = nullptr;
}

}  // namespace sl_projector
