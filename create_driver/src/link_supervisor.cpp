#include "create_driver/link_supervisor.h"

#include <algorithm>

namespace create_driver
{
const char* linkStateName(LinkState state)
{
  switch (state)
  {
    case LinkState::DISCONNECTED:
      return "disconnected";
    case LinkState::CONNECTING:
      return "connecting";
    case LinkState::STARTING:
      return "starting";
    case LinkState::RUNNING:
      return "running";
  }
  return "unknown";
}

LinkSupervisor::LinkSupervisor(const LinkParams& params) : params_(params), backoff_(params.initial_backoff) {}

LinkSupervisor::Action LinkSupervisor::tick(double now)
{
  switch (state_)
  {
    case LinkState::DISCONNECTED:
      if (now >= next_attempt_)
      {
        state_ = LinkState::CONNECTING;
        state_since_ = now;
        return Action::OPEN;
      }
      return Action::NONE;
    case LinkState::CONNECTING:
      return Action::NONE;
    case LinkState::STARTING:
      if (now - state_since_ > params_.start_timeout)
      {
        fail(now, "no valid sensor frame after the start sequence");
        return Action::CLOSE;
      }
      return Action::NONE;
    case LinkState::RUNNING:
      if (now - last_frame_ > params_.frame_timeout)
      {
        fail(now, "no valid sensor frame within the frame timeout");
        return Action::CLOSE;
      }
      return Action::NONE;
  }
  return Action::NONE;
}

void LinkSupervisor::openSucceeded(double now)
{
  if (state_ != LinkState::CONNECTING)
    return;
  state_ = LinkState::STARTING;
  state_since_ = now;
}

void LinkSupervisor::openFailed(double now, const std::string& error)
{
  ++failed_attempts_;
  fail(now, error);
}

void LinkSupervisor::ioError(double now, const std::string& error)
{
  if (state_ == LinkState::DISCONNECTED)
    return;
  fail(now, error);
}

void LinkSupervisor::validFrame(double now)
{
  last_frame_ = now;
  if (state_ == LinkState::STARTING)
  {
    state_ = LinkState::RUNNING;
    state_since_ = now;
    ++connects_;
    backoff_ = params_.initial_backoff;
  }
}

void LinkSupervisor::fail(double now, const std::string& error)
{
  if (state_ == LinkState::STARTING || state_ == LinkState::RUNNING)
    ++disconnects_;
  last_error_ = error;
  state_ = LinkState::DISCONNECTED;
  state_since_ = now;
  next_attempt_ = now + backoff_;
  backoff_ = std::min(params_.max_backoff, backoff_ * 2.0);
}

}  // namespace create_driver
