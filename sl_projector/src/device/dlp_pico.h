#pragma once
/// @file dlp_pico.h
/// @brief Set-up of a TI DLP Pico projector (DLPC2607 controller) over Linux i2c-dev (ROS-free).
/// Private to sl_projector (library sl_projector_device): not installed, not exported.

#include <cstdint>
#include <string>
#include <vector>

namespace sl_projector
{

/// @brief One register write: sub-address followed by a 32-bit value, most significant byte first.
struct I2cWrite
{
  uint8_t sub_address;  ///< register
  uint32_t data;        ///< value
  /// @brief The bytes on the bus after the device address: sub-address, then data MSB first.
  std::vector<uint8_t> bytes() const;
};

/**
 * @brief Register writes that make the projector show the frame buffer pixel for pixel when it is
 * mounted upside down: both axes flipped (sub-addresses 0x08 and 0x09, data 0) and "crop" instead
 * of "scale" display mode (sub-address 0x05, data 7), as used on the prototype.
 * @param flip include the two flip writes.
 * @param crop include the display-mode write.
 */
std::vector<I2cWrite> dlpPicoSetup(bool flip = true, bool crop = true);

/// @brief Formats writes as text, one per line: "addr 0x1b: 08 00 00 00 00".
std::string formatWrites(uint8_t device_address, const std::vector<I2cWrite>& writes);

/**
 * @brief Sends @p writes to the 7-bit @p device_address on the i2c-dev bus @p bus_path
 * (e.g. "/dev/i2c-2").
 * @throws std::runtime_error naming the bus and the failing step (open, address, write).
 */
void sendI2cWrites(const std::string& bus_path, uint8_t device_address, const std::vector<I2cWrite>& writes);

}  // namespace sl_projector
