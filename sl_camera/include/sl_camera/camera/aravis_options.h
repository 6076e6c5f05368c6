/**
 * @file
 * GigE Vision transport settings of the Aravis back-end. Plain data, available in every build
 * (parsing and validation live in camera_config.cpp, so a build without Aravis still checks them).
 */
#pragma once

#include <string>

namespace sl_camera
{

/** How GigE Vision stream packets are received. */
enum class PacketSocketMode
{
  /**
   * Aravis' packet socket where it can open one (it needs CAP_NET_RAW, e.g. root), except for a
   * camera reached through the loopback interface, where a packet socket receives nothing.
   */
  Auto,
  /** Never a packet socket: always an ordinary UDP socket. */
  Off
};

/** Transport settings for GigE Vision cameras; USB3 Vision and the Fake interface ignore them. */
struct AravisOptions
{
  PacketSocketMode packet_socket = PacketSocketMode::Auto;
  /** Receive buffer of the stream socket, bytes; 0: automatic (one frame's payload). */
  int socket_buffer = 0;
  /** GVSP packet size, bytes; 0: negotiated with the camera (largest that passes unfragmented). */
  int packet_size = 0;
};

/** Parameter spelling: "auto" or "off". */
const char* packetSocketModeName(PacketSocketMode mode);

/** Parses "auto" or "off"; @throws std::invalid_argument naming `packet_socket` otherwise. */
PacketSocketMode parsePacketSocketMode(const std::string& name);

/** Smallest and largest GVSP packet size accepted for `packet_size`, bytes. */
constexpr int kMinPacketSize = 576;
constexpr int kMaxPacketSize = 65500;
/** Smallest and largest explicit `socket_buffer`, bytes. */
constexpr int kMinSocketBuffer = 65536;
constexpr int kMaxSocketBuffer = 1 << 30;

}  // namespace sl_camera
