#pragma once
// Internal: what the data set's HDF5 writer and reader share.
#include <H5Cpp.h>

namespace eitbench::detail {

constexpr int kDatasetFormatVersion = 1;
constexpr int kMaxCircles = 4;

template <typename T>
const H5::PredType& h5_type();
template <>
inline const H5::PredType& h5_type<double>() {
  return H5::PredType::NATIVE_DOUBLE;
}
template <>
inline const H5::PredType& h5_type<float>() {
  return H5::PredType::NATIVE_FLOAT;
}
template <>
inline const H5::PredType& h5_type<int>() {
  return H5::PredType::NATIVE_INT;
}

template <>
inline const H5::PredType& h5_type<unsigned char>() {
  return H5::PredType::NATIVE_UCHAR;
}

}  // namespace eitbench::detail
