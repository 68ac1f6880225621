// PNG files through libpng's simplified API (encoding to memory, so that no C++ exception ever
// crosses libpng's C frames), written atomically (io/atomic_file.hpp).
#include <png.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <ostream>

#include "fdmsurf/error.hpp"
#include "fdmsurf/render.hpp"
#include "io/formats.hpp"
#include "io/atomic_file.hpp"

namespace fdmsurf {
namespace {

void check_image(const Image& image) {
    if (image.width == 0 || image.height == 0 ||
        image.rgba.size() != std::size_t(image.width) * image.height * 4)
        throw Error(ErrorCode::InvalidArgument,
                    "write_png: an image of " + std::to_string(image.width) + " x " +
                        std::to_string(image.height) + " pixels needs " +
                        std::to_string(std::size_t(image.width) * image.height * 4) +
                        " bytes of RGBA, not " + std::to_string(image.rgba.size()));
}

// The PNG file's bytes: RGB when every pixel is opaque, else RGBA; sRGB.
std::vector<unsigned char> encode(const Image& image) {
    check_image(image);
    const bool opaque = image.opaque();
    std::vector<unsigned char> rgb;
    const void* pixels = image.rgba.data();
    if (opaque) {
        rgb.resize(std::size_t(image.width) * image.height * 3);
        for (std::size_t i = 0, n = std::size_t(image.width) * image.height; i < n; ++i)
            std::memcpy(&rgb[3 * i], &image.rgba[4 * i], 3);
        pixels = rgb.data();
    }
    png_image png;
    std::memset(&png, 0, sizeof png);
    png.version = PNG_IMAGE_VERSION;
    png.width = image.width;
    png.height = image.height;
    png.format = opaque ? PNG_FORMAT_RGB : PNG_FORMAT_RGBA;
    // One pass into a buffer of the largest size the image can take (compressing twice, once
    // to size the buffer, doubles the time: 80 ms instead of 40 for 1024 x 768).
    png_alloc_size_t size = PNG_IMAGE_PNG_SIZE_MAX(png);
    std::vector<unsigned char> bytes(size);
    if (!png_image_write_to_memory(&png, bytes.data(), &size, 0, pixels, 0, nullptr))
        throw Error(ErrorCode::Internal, std::string("libpng: ") + png.message);
    bytes.resize(size);
    return bytes;
}

}  // namespace

void write_png(const Image& image, const std::string& path) {
    const std::vector<unsigned char> bytes = encode(image);
    detail::AtomicFile file(path);
    file.write(bytes.data(), bytes.size());
    file.commit();
}

void write_png(const Image& image, std::ostream& out, const std::string& name) {
    const std::vector<unsigned char> bytes = encode(image);
    detail::StreamSink sink(out, name);
    sink.write(bytes.data(), bytes.size());
    sink.finish();
}

Image read_png(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(ErrorCode::Io, "cannot open " + path + ": " + std::strerror(errno));
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)),
                                  std::istreambuf_iterator<char>());
    png_image png;
    std::memset(&png, 0, sizeof png);
    png.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_memory(&png, bytes.data(), bytes.size()))
        throw Error(ErrorCode::Format, path + ": not a PNG libpng can read (" + png.message + ")");
    png.format = PNG_FORMAT_RGBA;
    Image image;
    image.width = png.width;
    image.height = png.height;
    image.rgba.resize(PNG_IMAGE_SIZE(png));
    if (!png_image_finish_read(&png, nullptr, image.rgba.data(), 0, nullptr)) {
        png_image_free(&png);
        throw Error(ErrorCode::Format, path + ": " + png.message);
    }
    return image;
}

}  // namespace fdmsurf
