// Bytes as text: base64 (RFC 4648, section 4: the standard alphabet, '=' padding, no line breaks),
// and arrays of doubles through it as IEEE 754 binary64, little-endian, so that a JSON document
// carries numbers bit for bit in 10.7 characters each (a least-squares summary's factors).
// Written from the RFC; checked against its test vectors (tests/data/digest/base64_test.cpp).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace dynid {

std::string base64Encode(std::string_view bytes);
/// Throws InputError for a length that is not a multiple of 4, a character outside the alphabet,
/// padding anywhere but at the end, or non-zero bits in the padding.
std::string base64Decode(std::string_view text);

/// `count` doubles as base64 of their little-endian binary64 bytes.
std::string doublesToBase64(const double* values, std::size_t count);
/// The doubles of doublesToBase64. Throws InputError for bad base64 or a byte count that is not a
/// multiple of 8.
std::vector<double> doublesFromBase64(std::string_view text);

}  // namespace dynid
