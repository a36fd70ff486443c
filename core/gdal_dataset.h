#pragma once
// An owned GDAL dataset, closed by GDALClose as GDAL asks, and the driver
// registration every reader or writer needs once.
#include <gdal_priv.h>

#include <memory>

namespace c3d {

struct GdalDatasetCloser {
  void operator()(GDALDataset* d) const { GDALClose(d); }
};
using GdalDataset = std::unique_ptr<GDALDataset, GdalDatasetCloser>;

// Registers GDAL's drivers on the first call (callers need not remember).
inline void register_gdal_drivers() {
  static const bool registered = (GDALAllRegister(), true);
  (void)registered;
}

}  // namespace c3d
