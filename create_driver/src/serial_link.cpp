#include "create_driver/serial_link.h"

#include <termios.h>

#include <cmath>
#include <stdexcept>

#include <boost/asio/post.hpp>
#include <boost/asio/write.hpp>

namespace create_driver
{

void SerialLinkParams::validate() const
{
  auto require = [](bool ok, const char* message)
  {
    if (!ok)
      throw std::invalid_argument(message);
  };
  require(!port.empty(), "port must not be empty");
  require(baud > 0, "baud must be > 0");
  require(tick_period >= 0.001 && tick_period <= 0.1, "control_period must be in [0.001, 0.1] s");
  require(link.initial_backoff > 0.0 && std::isfinite(link.initial_backoff), "reconnect_initial_delay must be > 0");
  require(link.max_backoff >= link.initial_backoff && std::isfinite(link.max_backoff),
          "reconnect_max_delay must be >= reconnect_initial_delay");
  require(link.frame_timeout > 0.05 && std::isfinite(link.frame_timeout), "link_timeout must be > 0.05 s");
  require(link.start_timeout > 0.1 && std::isfinite(link.start_timeout), "start_timeout must be > 0.1 s");
}
double steadyNow()
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

SerialLink::SerialLink(const SerialLinkParams& params, Handlers handlers)
  : params_(params),
    handlers_(std::move(handlers)),
    supervisor_(params.link),
    work_(boost::asio::make_work_guard(io_)),
    port_(io_),
    timer_(io_)
{
  out_.reserve(512);
  pending_.reserve(params.max_pending_write + 512);
  inflight_.reserve(params.max_pending_write + 512);
}

SerialLink::~SerialLink()
{
  if (thread_.joinable())
  {
    io_.stop();
    thread_.join();
  }
  closePort();
}

void SerialLink::start()
{
  if (thread_.joinable())
    return;
  next_tick_ = std::chrono::steady_clock::now();
  boost::asio::post(io_, [this] { onTick(); });
  thread_ = std::thread([this] { io_.run(); });
}

void SerialLink::stop(const Bytes& final_bytes, double timeout_s)
{
  if (!thread_.joinable())
    return;
  auto done = std::make_shared<std::promise<void>>();
  std::future<void> fut = done->get_future();
  boost::asio::post(io_,
                    [this, final_bytes, done]
                    {
                      stopping_ = true;
                      timer_.cancel();
                      if (port_.is_open() && !final_bytes.empty())
                      {
                        drain_done_ = done;
                        Bytes copy = final_bytes;
                        write(copy);
                        if (!writing_)
                          finishDrain();
                      }
                      else
                      {
                        done->set_value();
                      }
                    });
  fut.wait_for(std::chrono::duration<double>(timeout_s));
  io_.stop();
  thread_.join();
  closePort();
}

void SerialLink::finishDrain()
{
  if (drain_done_)
  {
    drain_done_->set_value();
    drain_done_.reset();
  }
}

void SerialLink::requestControl()
{
  boost::asio::post(io_,
                    [this]
                    {
                      if (stopping_)
                        return;
                      const LinkState s = supervisor_.state();
                      if ((s == LinkState::STARTING || s == LinkState::RUNNING) && handlers_.on_tick)
                      {
                        out_.clear();
                        handlers_.on_tick(steadyNow(), out_);
                        write(out_);
                      }
                    });
}

SerialLinkStats SerialLink::stats() const
{
  std::lock_guard<std::mutex> lock(stats_mutex_);
  return stats_;
}

void SerialLink::updateStats()
{
  std::lock_guard<std::mutex> lock(stats_mutex_);
  stats_.state = supervisor_.state();
  stats_.last_error = supervisor_.lastError();
  stats_.connects = supervisor_.connects();
  stats_.disconnects = supervisor_.disconnects();
  stats_.failed_attempts = supervisor_.failedAttempts();
  stats_.backoff = supervisor_.backoff();
}

void SerialLink::scheduleTick()
{
  if (stopping_)
    return;
  const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(params_.tick_period));
  next_tick_ += period;
  const auto now = std::chrono::steady_clock::now();
  if (next_tick_ < now)
    next_tick_ = now + period;  // fell behind: do not try to catch up
  timer_.expires_at(next_tick_);
  timer_.async_wait(
      [this](const boost::system::error_code& ec)
      {
        if (!ec)
          onTick();
      });
}

void SerialLink::onTick()
{
  if (stopping_)
    return;
  const auto now_tp = std::chrono::steady_clock::now();
  const double lateness = std::chrono::duration<double>(now_tp - next_tick_).count();
  const double now = steadyNow();
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    ++stats_.ticks;
    if (lateness > params_.tick_period)
      ++stats_.overruns;
    if (lateness > stats_.max_lateness)
      stats_.max_lateness = lateness;
  }
  switch (supervisor_.tick(now))
  {
    case LinkSupervisor::Action::OPEN:
      notify(LinkState::CONNECTING, "");
      doOpen(now);
      break;
    case LinkSupervisor::Action::CLOSE:
      closePort();
      notify(LinkState::DISCONNECTED, supervisor_.lastError());
      break;
    case LinkSupervisor::Action::NONE:
      break;
  }
  const LinkState s = supervisor_.state();
  if ((s == LinkState::STARTING || s == LinkState::RUNNING) && handlers_.on_tick)
  {
    out_.clear();
    handlers_.on_tick(now, out_);
    write(out_);
  }
  scheduleTick();
}

void SerialLink::doOpen(double now)
{
  boost::system::error_code ec;
  port_.open(params_.port, ec);
  if (!ec)
    port_.set_option(boost::asio::serial_port_base::baud_rate(params_.baud), ec);
  if (!ec)
    port_.set_option(boost::asio::serial_port_base::character_size(8), ec);
  if (!ec)
    port_.set_option(boost::asio::serial_port_base::parity(boost::asio::serial_port_base::parity::none), ec);
  if (!ec)
    port_.set_option(boost::asio::serial_port_base::stop_bits(boost::asio::serial_port_base::stop_bits::one), ec);
  if (!ec)
    port_.set_option(boost::asio::serial_port_base::flow_control(boost::asio::serial_port_base::flow_control::none),
                     ec);
  if (ec)
  {
    boost::system::error_code ignored;
    port_.close(ignored);
    supervisor_.openFailed(now, "cannot open " + params_.port + ": " + ec.message());
    notify(LinkState::DISCONNECTED, supervisor_.lastError());
    return;
  }
  // Drop whatever the device sent before we were listening.
  ::tcflush(port_.native_handle(), TCIOFLUSH);
  ++generation_;
  writing_ = false;
  pending_.clear();
  supervisor_.openSucceeded(now);
  notify(LinkState::STARTING, "");
  out_.clear();
  if (handlers_.on_open)
    handlers_.on_open(now, out_);
  write(out_);
  startRead();
}

void SerialLink::startRead()
{
  const uint64_t gen = generation_;
  port_.async_read_some(boost::asio::buffer(read_buf_),
                        [this, gen](const boost::system::error_code& ec, std::size_t n)
                        {
                          if (gen != generation_ || stopping_)
                            return;
                          if (ec)
                          {
                            ioFailure("read failed on " + params_.port + ": " + ec.message());
                            return;
                          }
                          const double now = steadyNow();
                          {
                            std::lock_guard<std::mutex> lock(stats_mutex_);
                            stats_.bytes_read += n;
                          }
                          out_.clear();
                          const size_t frames =
                              handlers_.on_data ? handlers_.on_data(read_buf_.data(), n, now, out_) : 0;
                          if (frames > 0)
                          {
                            const LinkState before = supervisor_.state();
                            supervisor_.validFrame(now);
                            if (before != LinkState::RUNNING && supervisor_.state() == LinkState::RUNNING)
                              notify(LinkState::RUNNING, "");
                          }
                          write(out_);
                          if (gen == generation_)
                            startRead();
                        });
}

void SerialLink::write(Bytes& out)
{
  if (out.empty() || !port_.is_open())
    return;
  pending_.insert(pending_.end(), out.begin(), out.end());
  out.clear();
  if (pending_.size() > params_.max_pending_write)
  {
    ioFailure("write stalled on " + params_.port + " (device not reading)");
    return;
  }
  if (!writing_)
    startWrite();
}

void SerialLink::startWrite()
{
  inflight_.swap(pending_);
  pending_.clear();
  writing_ = true;
  const uint64_t gen = generation_;
  boost::asio::async_write(port_, boost::asio::buffer(inflight_),
                           [this, gen](const boost::system::error_code& ec, std::size_t n)
                           {
                             if (gen != generation_)
                               return;
                             writing_ = false;
                             if (ec)
                             {
                               ioFailure("write failed on " + params_.port + ": " + ec.message());
                               finishDrain();
                               return;
                             }
                             {
                               std::lock_guard<std::mutex> lock(stats_mutex_);
                               stats_.bytes_written += n;
                             }
                             inflight_.clear();
                             if (!pending_.empty())
                               startWrite();
                             else if (stopping_)
                               finishDrain();
                           });
}

void SerialLink::ioFailure(const std::string& error)
{
  supervisor_.ioError(steadyNow(), error);
  closePort();
  notify(LinkState::DISCONNECTED, error);
}

void SerialLink::closePort()
{
  ++generation_;
  writing_ = false;
  pending_.clear();
  if (port_.is_open())
  {
    boost::system::error_code ec;
    port_.cancel(ec);
    port_.close(ec);
  }
}

void SerialLink::notify(LinkState state, const std::string& reason)
{
  updateStats();
  if (handlers_.on_state && !stopping_)
    handlers_.on_state(state, reason);
}

}  // namespace create_driver
