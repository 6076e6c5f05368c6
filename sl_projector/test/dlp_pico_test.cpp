#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "device/dlp_pico.h"

using namespace sl_projector;

TEST(DlpPico, SetupBytesAreThePrototypes)
{
  const std::vector<I2cWrite> w = dlpPicoSetup();
  ASSERT_EQ(w.size(), 3u);
  EXPECT_EQ(w[0].bytes(), (std::vector<uint8_t>{ 0x08, 0, 0, 0, 0 }));
  EXPECT_EQ(w[1].bytes(), (std::vector<uint8_t>{ 0x09, 0, 0, 0, 0 }));
  EXPECT_EQ(w[2].bytes(), (std::vector<uint8_t>{ 0x05, 0, 0, 0, 7 }));
  EXPECT_EQ(dlpPicoSetup(false, true).size(), 1u);
  EXPECT_EQ((I2cWrite{ 0x12, 0x01020304u }.bytes()), (std::vector<uint8_t>{ 0x12, 1, 2, 3, 4 }));
  EXPECT_EQ(formatWrites(0x1b, dlpPicoSetup(false, true)), "addr 0x1b: 05 00 00 00 07\n");
}

TEST(DlpPico, MissingBusIsAClearError)
{
  try
  {
    sendI2cWrites("/dev/i2c-does-not-exist", 0x1b, dlpPicoSetup());
    FAIL() << "expected an error";
  }
  catch (const std::runtime_error& e)
  {
    EXPECT_NE(std::string(e.what()).find("/dev/i2c-does-not-exist"), std::string::npos) << e.what();
  }
  // A file that is not an I2C bus: opening works, selecting the address fails.
  EXPECT_THROW(sendI2cWrites("/dev/null", 0x1b, dlpPicoSetup()), std::runtime_error);
}
