#include "glare/wave/psf_exr.h"

#include "core/exr_io.h"

namespace glarelab {

void write_psf_exr(const std::string& path, const Psf& psf) {
  if (psf.channels != 1 && psf.channels != 3) throw ImageError(path + ": a PSF has 1 or 3 channels");
  const int n = psf.size_px;
  ImageRGBA image(n, n, 0.0f);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      float* pixel = image.pixel(x, y);
      for (int c = 0; c < 3; ++c) pixel[c] = static_cast<float>(psf.at(psf.channels == 3 ? c : 0, x, y));
      pixel[3] = 1.0f;
    }
  ExrWriteOptions options;
  options.pixel_type = ExrPixelType::float32;
  options.write_alpha = false;
  options.luminance_only = psf.channels == 1;
  options.float_attributes["degreesPerPixel"] = static_cast<float>(psf.degrees_per_pixel);
  write_exr(path, image, options);
}

Psf read_psf_exr(const std::string& path) {
  const ExrReadResult file = read_exr(path);
  const auto attribute = file.float_attributes.find("degreesPerPixel");
  if (attribute == file.float_attributes.end()) throw ImageError(path + ": no degreesPerPixel attribute: not a PSF");
  if (file.image.width_px != file.image.height_px) throw ImageError(path + ": a PSF is square");
  // Y-only files read as grey RGB; a PSF whose three channels are equal is stored as one.
  bool grey = true;
  for (std::size_t k = 0; k + 3 < file.image.rgba.size() && grey; k += 4)
    grey = file.image.rgba[k] == file.image.rgba[k + 1] && file.image.rgba[k] == file.image.rgba[k + 2];
  Psf psf;
  psf.size_px = file.image.width_px;
  psf.degrees_per_pixel = attribute->second;
  psf.channels = grey ? 1 : 3;
  psf.values.assign(static_cast<std::size_t>(psf.channels) * psf.size_px * psf.size_px, 0.0);
  for (int c = 0; c < psf.channels; ++c)
    for (int y = 0; y < psf.size_px; ++y)
      for (int x = 0; x < psf.size_px; ++x) psf.at(c, x, y) = file.image.pixel(x, y)[c];
  return psf;
}

}  // namespace glarelab
