// The library layout (README.md, "Code layout"): the driver's libraries never link the simulator,
// and the simulator links the Open Interface alone, never the driver's control. Read from the
// built shared libraries' dynamic sections (readelf -d), following the package's own libraries.
#include <gtest/gtest.h>

#include <cstdio>
#include <set>
#include <string>

namespace
{
// Direct dependencies (DT_NEEDED entries) of a shared library; *error set when readelf fails.
std::set<std::string> neededOf(const std::string& path, std::string* error)
{
  std::set<std::string> names;
  FILE* pipe = popen(("readelf -d '" + path + "' 2>&1").c_str(), "r");
  if (pipe == nullptr)
  {
    *error = "cannot run readelf for " + path;
    return names;
  }
  std::string output;
  char buf[512];
  while (fgets(buf, sizeof(buf), pipe) != nullptr)
    output += buf;
  if (pclose(pipe) != 0)
  {
    *error = "readelf -d " + path + " failed (binutils installed?): " + output;
    return names;
  }
  const std::string tag = "Shared library: [";
  for (size_t at = output.find(tag); at != std::string::npos; at = output.find(tag, at))
  {
    at += tag.size();
    names.insert(output.substr(at, output.find(']', at) - at));
  }
  return names;
}

// This package's libraries (libcreate_*) that @p path needs, directly or through one another;
// they are built into the same folder.
std::set<std::string> packageLibrariesOf(const std::string& path)
{
  const std::string dir = path.substr(0, path.rfind('/') + 1);
  std::set<std::string> found;
  std::set<std::string> todo = { path };
  while (!todo.empty())
  {
    const std::string next = *todo.begin();
    todo.erase(todo.begin());
    std::string error;
    for (const std::string& name : neededOf(next, &error))
      if (name.rfind("libcreate_", 0) == 0 && found.insert(name).second)
        todo.insert(dir + name);
    EXPECT_TRUE(error.empty()) << error;
  }
  return found;
}

bool isSharedLibrary(const std::string& path)
{
  return path.size() > 3 && path.compare(path.size() - 3, 3, ".so") == 0;
}
}  // namespace

TEST(LinkLayout, TheDriverNeverLinksTheSimulator)
{
  for (const std::string lib : { CREATE_DRIVER_CORE_LIB, CREATE_DRIVER_NODELETS_LIB })
  {
    if (!isSharedLibrary(lib))
      GTEST_SKIP() << lib << " is not a shared library: no dynamic section to read";
    const std::set<std::string> libs = packageLibrariesOf(lib);
    EXPECT_EQ(libs.count("libcreate_oi.so"), 1u) << lib;
    EXPECT_EQ(libs.count("libcreate_sim_core.so"), 0u) << lib;
    EXPECT_EQ(libs.count("libcreate_sim_nodelets.so"), 0u) << lib;
  }
}

TEST(LinkLayout, TheSimulatorLinksTheOpenInterfaceOnly)
{
  for (const std::string lib : { CREATE_SIM_CORE_LIB, CREATE_SIM_NODELETS_LIB })
  {
    if (!isSharedLibrary(lib))
      GTEST_SKIP() << lib << " is not a shared library: no dynamic section to read";
    std::set<std::string> libs = packageLibrariesOf(lib);
    libs.erase("libcreate_sim_core.so");
    EXPECT_EQ(libs, std::set<std::string>({ "libcreate_oi.so" })) << lib;
  }
}
