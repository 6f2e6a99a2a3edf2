#include "features/exif_focal.h"

#include <libexif/exif-data.h>
#include <libexif/exif-loader.h>
#include <libexif/exif-log.h>
#include <libexif/exif-utils.h>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <optional>

namespace pgba {

namespace {

// libexif reports corrupt data through its log; the first message is kept to name the problem.
struct CorruptionLog {
  std::string first_message;
};

void OnExifLog(ExifLog*, ExifLogCode code, const char* domain, const char* format, va_list args, void* user) {
  if (code != EXIF_LOG_CODE_CORRUPT_DATA && code != EXIF_LOG_CODE_NO_MEMORY) return;
  auto* log = static_cast<CorruptionLog*>(user);
  if (!log->first_message.empty()) return;
  char text[256];
  std::vsnprintf(text, sizeof(text), format, args);
  log->first_message = std::string(domain ? domain : "libexif") + ": " + text;
}

// The first value of a numeric tag (EXIF IFD first, then IFD0; never the thumbnail's IFD1),
// or nothing when absent, of a non-numeric format, too short, or a rational over zero.
std::optional<double> NumericTag(ExifData* data, ExifTag tag) {
  ExifEntry* e = exif_content_get_entry(data->ifd[EXIF_IFD_EXIF], tag);
  if (e == nullptr) e = exif_content_get_entry(data->ifd[EXIF_IFD_0], tag);
  if (e == nullptr || e->data == nullptr || e->components < 1) return std::nullopt;
  const unsigned int element = exif_format_get_size(e->format);
  if (element == 0 || e->size < element) return std::nullopt;
  const ExifByteOrder order = exif_data_get_byte_order(data);
  switch (e->format) {
    case EXIF_FORMAT_BYTE:
      return static_cast<double>(e->data[0]);
    case EXIF_FORMAT_SHORT:
      return static_cast<double>(exif_get_short(e->data, order));
    case EXIF_FORMAT_SSHORT:
      return static_cast<double>(exif_get_sshort(e->data, order));
    case EXIF_FORMAT_LONG:
      return static_cast<double>(exif_get_long(e->data, order));
    case EXIF_FORMAT_SLONG:
      return static_cast<double>(exif_get_slong(e->data, order));
    case EXIF_FORMAT_RATIONAL: {
      const ExifRational r = exif_get_rational(e->data, order);
      if (r.denominator == 0) return std::nullopt;
      return static_cast<double>(r.numerator) / r.denominator;
    }
    case EXIF_FORMAT_SRATIONAL: {
      const ExifSRational r = exif_get_srational(e->data, order);
      if (r.denominator == 0) return std::nullopt;
      return static_cast<double>(r.numerator) / r.denominator;
    }
    default:
      return std::nullopt;
  }
}

// Pixels per mm of FocalPlaneResolutionUnit (EXIF: 2 inch, 3 cm; COLMAP also takes 4 mm, 5 um).
std::optional<double> UnitsPerMm(double unit) {
  if (unit == 2) return 1.0 / 25.4;
  if (unit == 3) return 1.0 / 10.0;
  if (unit == 4) return 1.0;
  if (unit == 5) return 1000.0;
  return std::nullopt;
}

// Rules 1 and 2 of the header on parsed EXIF; nothing if neither applies.
std::optional<FocalPrior> FocalFromTags(ExifData* data, int width, int height) {
  const std::optional<double> f35 = NumericTag(data, EXIF_TAG_FOCAL_LENGTH_IN_35MM_FILM);
  if (f35 && *f35 > 0) {
    const double diagonal = std::hypot(static_cast<double>(width), static_cast<double>(height));
    return FocalPrior{*f35 / 43.27 * diagonal, FocalSource::kExif35mm, ""};
  }
  const std::optional<double> f_mm = NumericTag(data, EXIF_TAG_FOCAL_LENGTH);
  const std::optional<double> x_res = NumericTag(data, EXIF_TAG_FOCAL_PLANE_X_RESOLUTION);
  const std::optional<double> unit = NumericTag(data, EXIF_TAG_FOCAL_PLANE_RESOLUTION_UNIT);
  if (f_mm && *f_mm > 0 && x_res && *x_res > 0 && unit) {
    if (const std::optional<double> per_mm = UnitsPerMm(*unit))
      return FocalPrior{*f_mm * *x_res * *per_mm, FocalSource::kExifFocalPlane, ""};
  }
  return std::nullopt;
}

}  // namespace

const char* FocalSourceName(FocalSource source) {
  switch (source) {
    case FocalSource::kExif35mm:
      return "EXIF FocalLengthIn35mmFilm";
    case FocalSource::kExifFocalPlane:
      return "EXIF FocalLength + FocalPlaneXResolution";
    case FocalSource::kDefault:
      break;
  }
  return "default prior";
}

double DefaultFocalPx(int width, int height) { return 1.2 * std::max(width, height); }

FocalPrior ExifFocalPrior(const std::string& path, int width, int height) {
  FocalPrior fallback{DefaultFocalPx(width, height), FocalSource::kDefault, ""};
  CorruptionLog corruption;
  ExifLog* log = exif_log_new();
  if (log == nullptr) return fallback;
  exif_log_set_func(log, OnExifLog, &corruption);

  // The loader finds the EXIF block (JPEG APP1, or a raw EXIF file) without decoding the
  // image; anything else (PNG, TIFF, ...) leaves its buffer empty. It gets no log: it reports
  // a file without EXIF as corrupt data, and that is the normal case of a PNG.
  ExifLoader* loader = exif_loader_new();
  ExifData* data = nullptr;
  if (loader != nullptr) {
    exif_loader_write_file(loader, path.c_str());
    const unsigned char* buf = nullptr;
    unsigned int size = 0;
    exif_loader_get_buf(loader, &buf, &size);
    if (buf != nullptr && size > 0 && (data = exif_data_new()) != nullptr) {
      exif_data_log(data, log);
      // Read the tags as written: following the specification would add missing mandatory
      // tags with default values, which must not pass for a camera's metadata.
      exif_data_unset_option(data, EXIF_DATA_OPTION_FOLLOW_SPECIFICATION);
      exif_data_load_data(data, buf, size);
    }
    exif_loader_unref(loader);
  }

  std::optional<FocalPrior> prior;
  if (data != nullptr) {
    prior = FocalFromTags(data, width, height);
    exif_data_unref(data);
  }
  exif_log_unref(log);

  const double longer = std::max(width, height);
  if (prior &&
      !(std::isfinite(prior->focal_px) && prior->focal_px >= 0.1 * longer && prior->focal_px <= 100 * longer)) {
    char text[160];
    std::snprintf(text, sizeof(text), "implausible focal %.1f px from %s", prior->focal_px,
                  FocalSourceName(prior->source));
    fallback.problem = text;
    return fallback;
  }
  if (prior) return *prior;
  if (!corruption.first_message.empty()) fallback.problem = "corrupt EXIF block (" + corruption.first_message + ")";
  return fallback;
}

}  // namespace pgba
