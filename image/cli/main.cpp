// glint-image: inspect, compare and convert Glint's layered EXRs (docs/image.md).
#include <CLI/CLI.hpp>

#include "cli_boundary.h"
#include "commands.h"

int main(int argc, char** argv) {
    CLI::App app{"Inspect, compare and convert Glint's layered EXR images.", "glint-image"};
    app.require_subcommand(1);
    // One --json for every command, given before or after the command's own arguments.
    bool json = false;
    app.add_flag("--json", json, "Print one JSON object on stdout (info, diff, merge)");
    app.fallthrough();

    glint::cli::InfoOptions info;
    CLI::App* infoCmd = app.add_subcommand("info", "Size, layers, metadata and NaN/Inf counts");
    infoCmd->add_option("FILE", info.file, "Image (layered EXR or any OpenImageIO format)")
        ->required();

    glint::cli::DiffOptions diff;
    CLI::App* diffCmd = app.add_subcommand("diff", "Error metric of an image against a reference");
    diffCmd->add_option("FILE", diff.file, "Image to evaluate")->required();
    diffCmd->add_option("--reference", diff.reference, "Reference image")->required();
    diffCmd
        ->add_option("--metric,--expect", diff.metrics,
                     "ssim | psnr | mse | relmse | flip | flip-ldr | flip-hdr, or an expectation "
                     "that sets the exit code: 'ssim>=0.98', 'flip<=0.05', mc[:ALPHA] "
                     "(repeatable; --expect is the same option)")
        ->take_all()
        ->allow_extra_args(false);
    diffCmd->add_option("--error-map", diff.errorMap, "Write FLIP's error map (magma) as a PNG");
    diffCmd->add_option("--crop", diff.crop, "Pixel rectangle x0,x1,y0,y1 (half-open)");
    diffCmd->add_flag("--linear", diff.linear, "SSIM on linear values instead of display values");
    diffCmd->add_option("--exposure", diff.exposure, "Exposure in stops for display values");

    glint::cli::ConvertOptions convert;
    CLI::App* convertCmd = app.add_subcommand("convert", "Write an 8-bit sRGB PNG of a layer");
    convertCmd->add_option("IN", convert.input, "Input image")->required();
    convertCmd->add_option("OUT", convert.output, "Output .png")->required();
    convertCmd->add_option("--exposure", convert.exposure, "Exposure in stops");
    convertCmd->add_option("--layer", convert.layer,
                           "Layer (color, albedo, normal, depth...) or one channel (albedo.G)");
    convertCmd->add_option("--false-color", convert.falseColor,
                           "Show one channel in false colour over lo,hi");

    glint::cli::MergeOptions merge;
    CLI::App* mergeCmd = app.add_subcommand(
        "merge", "Merge the shards of a render (glint-render --shard i/N) into the whole frame");
    mergeCmd
        ->add_option("SHARD", merge.shards,
                     "Shard EXRs and partial merges that together hold every shard of the "
                     "render once, in any order")
        ->required();
    mergeCmd->add_flag("--partial", merge.partial,
                       "Merge a contiguous range of shards a..b into a file recording "
                       "glint:shard \"a-b/N\", which a later merge accepts like a shard");
    mergeCmd->add_option("--out", merge.output, "Merged EXR (.exr)")->required();

    if (const auto code = glint::cli::parseCommandLine(app, argc, argv, "glint-image"))
        return *code;
    info.json = diff.json = merge.json = json;
    return glint::cli::runGuarded("glint-image", [&] {
        if (*infoCmd) glint::cli::runInfo(info);
        if (*diffCmd) return glint::cli::runDiff(diff);
        if (*convertCmd) glint::cli::runConvert(convert);
        if (*mergeCmd) glint::cli::runMerge(merge);
        return 0;
    });
}
