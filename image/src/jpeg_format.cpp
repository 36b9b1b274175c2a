// JPEG read through libjpeg-turbo, without the OpenImageIO module (direct_formats.h): grey as one
// channel, YCbCr and RGB as RGB, sRGB-encoded; CMYK, YCCK and unknown colour models are left to
// the module. A JPEG's data that ends early (libjpeg's warning, after which it pads the image with
// grey) is an error, a scan cut short by a marker included, and so is a file without its
// end-of-image marker (truncated), found before libjpeg sees it. libjpeg reports errors by longjmp:
// the function that sets the jump holds nothing that needs destroying.
#include <algorithm>
#include <csetjmp>
#include <cstdio>
#include <memory>
#include <vector>
// jpeglib.h needs <cstdio> before it.
#include <jerror.h>
#include <jpeglib.h>

#include "direct_formats.h"
#include "glint/image/error.h"
#include "image_files.h"

namespace glint::detail {

namespace {

bool isJpeg(std::span<const unsigned char> bytes) {
    return bytes.size() >= 3 && bytes[0] == 0xff && bytes[1] == 0xd8 && bytes[2] == 0xff;
}

void checkJpeg(std::span<const unsigned char> bytes, const std::string& file) {
    // The end-of-image marker closes the file (a few trailing bytes are tolerated).
    const std::size_t tail = std::min<std::size_t>(bytes.size(), 64);
    for (std::size_t i = bytes.size() - tail; i + 1 < bytes.size(); ++i)
        if (bytes[i] == 0xff && bytes[i + 1] == 0xd9) return;
    throw Error(ErrorKind::Format, "truncated JPEG (no end-of-image marker)", file,
                "byte " + std::to_string(bytes.size()));
}

/// libjpeg's error manager, where its callbacks jump to, and what they reported.
struct JpegErrors {
    jpeg_error_mgr manager{};
    std::jmp_buf jump{};
    const char* stage = "header";
    char message[JMSG_LENGTH_MAX] = "";
    bool endedEarly = false;
};

[[noreturn]] void onError(j_common_ptr jpeg) {
    auto* errors = reinterpret_cast<JpegErrors*>(jpeg->err);
    (*jpeg->err->format_message)(jpeg, errors->message);
    std::longjmp(errors->jump, 1);
}

// libjpeg would print its warnings on stderr. Data that ends early — the file's end, or a marker
// inside a scan — is kept as an error (libjpeg pads the rest with grey); the others (extraneous
// bytes before a marker) leave a readable image.
void onMessage(j_common_ptr jpeg, int level) {
    if (level == -1 &&
        (jpeg->err->msg_code == JWRN_JPEG_EOF || jpeg->err->msg_code == JWRN_HIT_MARKER))
        reinterpret_cast<JpegErrors*>(jpeg->err)->endedEarly = true;
}

/// Reads the header and the samples of every row into `samples`; false after a libjpeg error,
/// `declined` for an image of another colour model than grey, YCbCr and RGB.
bool decode(jpeg_decompress_struct& jpeg, JpegErrors& errors, std::span<const unsigned char> bytes,
            const SizeCheck& check, std::unique_ptr<unsigned char[]>& samples, bool& declined) {
    if (setjmp(errors.jump)) return false;
    jpeg_create_decompress(&jpeg);
    jpeg_mem_src(&jpeg, bytes.data(), static_cast<unsigned long>(bytes.size()));
    jpeg_read_header(&jpeg, TRUE);
    if (jpeg.jpeg_color_space != JCS_GRAYSCALE && jpeg.jpeg_color_space != JCS_YCbCr &&
        jpeg.jpeg_color_space != JCS_RGB) {
        declined = true;  // CMYK, YCCK, or a colour model libjpeg does not know
        return true;
    }
    const int channels = jpeg.num_components == 1 ? 1 : 3;
    check(int(jpeg.image_width), int(jpeg.image_height), channels);
    jpeg.out_color_space = channels == 1 ? JCS_GRAYSCALE : JCS_RGB;
    errors.stage = "pixels";
    jpeg_start_decompress(&jpeg);
    const std::size_t rowBytes = std::size_t(jpeg.output_width) * std::size_t(channels);
    samples.reset(new unsigned char[rowBytes * jpeg.output_height]);  // libjpeg fills it
    while (jpeg.output_scanline < jpeg.output_height) {
        JSAMPROW row = samples.get() + rowBytes * jpeg.output_scanline;
        jpeg_read_scanlines(&jpeg, &row, 1);
    }
    jpeg_finish_decompress(&jpeg);
    return true;
}

bool readJpeg(std::span<const unsigned char> bytes, const std::string& file, const SizeCheck& check,
              DecodedImage& out, Image& pixels) {
    JpegErrors errors;
    jpeg_decompress_struct jpeg{};
    jpeg.err = jpeg_std_error(&errors.manager);
    errors.manager.error_exit = onError;
    errors.manager.emit_message = onMessage;
    // Created in decode(); destroying one never created (mem still null) does nothing.
    struct Release {
        jpeg_decompress_struct& jpeg;
        ~Release() { jpeg_destroy_decompress(&jpeg); }
    } release{jpeg};

    std::unique_ptr<unsigned char[]> samples;
    bool declined = false;
    if (!decode(jpeg, errors, bytes, check, samples, declined))
        throw Error(ErrorKind::Format, std::string("damaged JPEG: ") + errors.message, file,
                    errors.stage);
    if (declined) return false;
    if (errors.endedEarly)
        throw Error(ErrorKind::Format, "truncated JPEG (its data ends early)", file, "pixels");
    out.width = int(jpeg.output_width);
    out.height = int(jpeg.output_height);
    out.channels = jpeg.output_components;
    out.alphaChannel = -1;
    out.eightBit = true;
    out.colorSpace = "sRGB";
    // As OpenImageIO converts: a sample times the reciprocal of its largest value.
    pixels = Image(out.width, out.height, out.channels);
    const std::span<float> values = pixels.data();
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = float(samples[i]) * (1.0f / 255.0f);
    return true;
}

}  // namespace

const DirectFormat kJpegFormat{"jpeg", ".jpg", isJpeg, checkJpeg, readJpeg, nullptr};

}  // namespace glint::detail
