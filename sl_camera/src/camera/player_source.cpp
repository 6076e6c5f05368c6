#include "sl_camera/camera/player_source.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <memory>
#include <system_error>
#include <thread>
#include <utility>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "sl_rig/mono8.h"

namespace fs = std::filesystem;

namespace sl_camera
{

namespace
{
struct SteadyPacingClock : PlayerSource::PacingClock
{
  std::chrono::steady_clock::time_point now() override { return std::chrono::steady_clock::now(); }
  void sleepUntil(std::chrono::steady_clock::time_point t) override { std::this_thread::sleep_until(t); }
};

std::string lowerExtension(const std::string& path)
{
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}
}  // namespace

bool PlayerSource::isImageFile(const std::string& path)
{
  static const char* const extensions[] = { ".png", ".jpg", ".jpeg", ".pgm", ".ppm", ".pnm", ".bmp", ".tif", ".tiff" };
  const std::string ext = lowerExtension(path);
  return std::any_of(std::begin(extensions), std::end(extensions), [&](const char* e) { return ext == e; });
}

PlayerSource::PlayerSource(const std::string& path, double rate, bool loop)
  : FrameSource("player of " + path),
    path_(path),
    rate_(rate),
    loop_(loop),
    clock_(std::make_shared<SteadyPacingClock>()),
    unreadable_(std::make_shared<UnreadableFiles>())
{
  if (!(rate > 0.0) || !std::isfinite(rate))
    throw std::invalid_argument("player rate must be a finite rate > 0 Hz, got " + std::to_string(rate));
  setNominalRate(rate);
}

PlayerSource::~PlayerSource()
{
  close();
}

void PlayerSource::open()
{
  close();
  std::error_code ec;
  const fs::file_status status = fs::status(path_, ec);
  if (path_.empty() || !fs::exists(status))
    throw CameraError(CameraError::Kind::NotFound,
                      "player: " + (path_.empty() ? std::string("(empty path)") : path_) + " does not exist");
  if (fs::is_directory(status))
  {
    std::vector<std::string> files;
    for (fs::directory_iterator it(path_, ec), end; !ec && it != end; it.increment(ec))
    {
      std::error_code file_ec;
      if (it->is_regular_file(file_ec) && isImageFile(it->path().string()))
        files.push_back(it->path().string());
    }
    if (ec)
      throw CameraError(CameraError::Kind::Open, "player: cannot list folder " + path_ + ": " + ec.message());
    if (files.empty())
      throw CameraError(CameraError::Kind::Open,
                        "player: no images (png, jpg, jpeg, pgm, ppm, pnm, bmp, tif, tiff) in folder " + path_);
    std::sort(files.begin(), files.end());
    files_.swap(files);
  }
  else if (isImageFile(path_))
  {
    files_.assign(1, path_);
  }
  else
  {
    video_.reset(new cv::VideoCapture());
    if (!openVideo())
    {
      video_.reset();
      throw CameraError(CameraError::Kind::Open, "player: cannot open " + path_ +
                                                     " as a video (not an image extension, and OpenCV cannot read it)");
    }
  }
  next_index_ = 0;
  sequence_ = 0;
  started_ = false;
  open_ = true;
}

void PlayerSource::close()
{
  if (video_)
  {
    video_->release();
    video_.reset();
  }
  files_.clear();
  open_ = false;
}

bool PlayerSource::isOpen() const
{
  return open_;
}

bool PlayerSource::waiting() const
{
  return open_ && gate_ && !gate_->isOpen();
}

void PlayerSource::setStartGate(std::shared_ptr<const StartGate> gate)
{
  gate_ = std::move(gate);
}

bool PlayerSource::openVideo()
{
  // FFmpeg reads nearly every container; OpenCV's own MJPEG reader needs no codec library. Other
  // back-ends (GStreamer, image sequences) are left out: they would guess at files that are no video.
  for (int api : { static_cast<int>(cv::CAP_FFMPEG), static_cast<int>(cv::CAP_OPENCV_MJPEG) })
  {
    try
    {
      if (video_->open(path_, api) && video_->isOpened())
        return true;
    }
    catch (const cv::Exception&)
    {
      // try the next back-end
    }
  }
  return false;
}

bool PlayerSource::readVideoFrame(cv::Mat& image)
{
  try
  {
    return video_->read(image) && !image.empty();
  }
  catch (const cv::Exception&)
  {
    return false;
  }
}

void PlayerSource::setPacingClock(std::shared_ptr<PacingClock> clock)
{
  if (!clock)
    throw std::invalid_argument("player: pacing clock is null");
  clock_ = std::move(clock);
}

GrabStatus PlayerSource::grab(Frame& frame, std::chrono::milliseconds timeout)
{
  using std::chrono::steady_clock;
  if (!open_)
    throw CameraError(CameraError::Kind::Lost, description() + ": not open");

  // Held before the start: wait on the gate (not a sleep), so the start is not delayed.
  if (gate_ && !gate_->waitFor(timeout))
    return GrabStatus::Timeout;

  const bool at_end = video_ ? false : next_index_ >= files_.size();
  if (at_end && !loop_)
    return GrabStatus::EndOfStream;

  // Pacing: one frame per period; a consumer that fell behind does not cause a burst.
  const auto period = std::chrono::duration_cast<steady_clock::duration>(std::chrono::duration<double>(1.0 / rate_));
  steady_clock::time_point now = clock_->now();
  if (!started_)
  {
    next_due_ = now;
    started_ = true;
  }
  if (now < next_due_)
  {
    if (next_due_ - now > timeout)
    {
      clock_->sleepUntil(now + timeout);
      return GrabStatus::Timeout;
    }
    clock_->sleepUntil(next_due_);
    now = clock_->now();
  }
  next_due_ += period;
  if (next_due_ < now)
    next_due_ = now + period;

  if (video_)
  {
    if (!readVideoFrame(video_frame_))
    {
      if (!loop_)
        return GrabStatus::EndOfStream;
      // Rewind (re-open when the container cannot seek).
      bool rewound = false;
      try
      {
        rewound = video_->set(cv::CAP_PROP_POS_FRAMES, 0) && readVideoFrame(video_frame_);
      }
      catch (const cv::Exception&)
      {
        rewound = false;
      }
      if (!rewound)
      {
        video_->release();
        rewound = openVideo() && readVideoFrame(video_frame_);
      }
      if (!rewound)
        throw CameraError(CameraError::Kind::Lost, "player: cannot read a frame from video " + path_);
    }
    try
    {
      sl_rig::toMono8(video_frame_, frame.image);
    }
    catch (const std::invalid_argument& e)
    {
      throw CameraError(CameraError::Kind::Frame, "player: video " + path_ + ": " + e.what());
    }
  }
  else
  {
    if (next_index_ >= files_.size())
      next_index_ = 0;  // loop
    const std::string& file = files_[next_index_++];
    std::error_code ec;
    if (!fs::exists(file, ec))  // the recording went away: re-open (and list) it later
      throw CameraError(CameraError::Kind::Lost, "player: image " + file + " disappeared");
    cv::Mat raw;
    try
    {
      raw = cv::imread(file, cv::IMREAD_UNCHANGED);
    }
    catch (const cv::Exception&)
    {
      raw.release();
    }
    if (raw.empty())
    {
      unreadable_->add(file);
      throw CameraError(CameraError::Kind::Frame, "player: cannot read image " + file + " (unreadable or corrupt)");
    }
    try
    {
      sl_rig::toMono8(raw, frame.image);
    }
    catch (const std::invalid_argument& e)
    {
      unreadable_->add(file);
      throw CameraError(CameraError::Kind::Frame, "player: image " + file + ": " + e.what());
    }
  }
  frame.stamp = CaptureClock::now();
  frame.sequence = sequence_++;
  frame.has_sequence = true;
  return GrabStatus::Frame;
}

}  // namespace sl_camera
