#include "sl_camera/camera/unreadable_files.h"

#include <algorithm>

namespace sl_camera
{

bool UnreadableFiles::add(const std::string& file)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (!known_.insert(file).second)
    return false;
  files_.push_back(file);
  return true;
}

std::size_t UnreadableFiles::count() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return files_.size();
}

std::vector<std::string> UnreadableFiles::first(std::size_t n) const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return std::vector<std::string>(files_.begin(), files_.begin() + std::min(n, files_.size()));
}

std::vector<std::string> UnreadableFiles::from(std::size_t index) const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return std::vector<std::string>(files_.begin() + std::min(index, files_.size()), files_.end());
}

std::string UnreadableFiles::summary(std::size_t max_names) const
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (files_.empty())
    return "none";
  const std::size_t shown = std::min(max_names, files_.size());
  std::string text = join(std::vector<std::string>(files_.begin(), files_.begin() + shown));
  if (shown < files_.size())
    text += (shown > 0 ? " and " : "") + std::to_string(files_.size() - shown) + " more";
  return text;
}

std::string UnreadableFiles::join(const std::vector<std::string>& names)
{
  std::string text;
  for (const std::string& n : names)
    text += (text.empty() ? "" : ", ") + n;
  return text;
}

std::vector<std::string> UnreadableFilesLog::due(const UnreadableFiles& files, double now)
{
  if (have_logged_ && now - last_ < interval_)
    return {};
  std::vector<std::string> fresh = files.from(logged_);
  if (fresh.empty())
    return fresh;
  logged_ += fresh.size();
  have_logged_ = true;
  last_ = now;
  return fresh;
}

}  // namespace sl_camera
