// pgba convert eth3d --scene SCENE --out OUT [--calibration DIR] [--images-root DIR] [--copy]
// pgba convert eth3d-slam --sequence DIR --out OUT [--max-dt S] [--copy]
// pgba convert tanks --log SCENE_COLMAP_SfM.log --images DIR --cameras cameras.txt --out OUT
//                    [--image-list FILE] [--copy]
//
// Public benchmark datasets into the layout `pgba run` / `pgba benchmark` read: OUT/images/
// (links to the photos, or copies with --copy), OUT/cameras.txt, OUT/camera_map.txt (several
// cameras only) and OUT/gt/ (ground-truth poses, COLMAP text). datasets/README.md has the
// downloads and the full recipes.
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "apps/commands.h"
#include "pgba/io/dataset_layout.h"
#include "pgba/io/eth3d.h"
#include "pgba/io/eth3d_slam.h"
#include "pgba/io/tanks_and_temples.h"
#include "pgba/util/output_path.h"

namespace pgba::app {

namespace {
// The output dataset folder apart from every input (before anything is read or written):
// converting into the dataset's own folder replaced each photo by a link to itself.
void CheckConvertOutput(const std::string& out, const std::vector<NamedInput>& inputs) {
  RequireOutputPath(out, "--out");
  CheckOutputDirApartFromInputs(out, kDatasetLayoutEntries, inputs);
}

std::string Under(const std::string& root, const std::string& p) {
  return std::filesystem::path(p).is_absolute() ? p : (std::filesystem::path(root) / p).string();
}
}  // namespace

void RegisterConvert(CLI::App& app) {
  CLI::App* convert = app.add_subcommand("convert", "Public datasets (ETH3D, ETH3D SLAM, Tanks and Temples) -> images/ cameras.txt gt/");
  convert->require_subcommand(1);

  struct Eth3dArgs {
    std::string scene, out;
    Eth3dOptions options;
  };
  auto eth = std::make_shared<Eth3dArgs>();
  CLI::App* e = convert->add_subcommand("eth3d", "ETH3D high-res multi-view scene (undistorted DSLR, COLMAP GT)");
  e->add_option("--scene", eth->scene, "Scene folder (holds images/ and dslr_calibration_undistorted/)")->required();
  e->add_option("--out", eth->out, "Output dataset folder")->required();
  e->add_option("--calibration", eth->options.calibration_dir, "Calibration folder, relative to the scene")
      ->capture_default_str();
  e->add_option("--images-root", eth->options.images_root, "Folder the image names are relative to")
      ->capture_default_str();
  e->add_flag("--copy", eth->options.layout.copy_images, "Copy the photos instead of linking them");
  AddCommand(app, e, [eth] {
    CheckConvertOutput(eth->out, {{"--scene", eth->scene},
                                  {"--calibration", Under(eth->scene, eth->options.calibration_dir)},
                                  {"--images-root", Under(eth->scene, eth->options.images_root)}});
    const size_t n = ConvertEth3dScene(eth->scene, eth->out, eth->options);
    std::cout << "pgba convert eth3d: " << n << " images -> " << eth->out << "/{images/, cameras.txt, gt/}\n";
    return 0;
  });

  struct SlamArgs {
    std::string sequence, out;
    Eth3dSlamOptions options;
  };
  auto slam = std::make_shared<SlamArgs>();
  CLI::App* l = convert->add_subcommand("eth3d-slam", "ETH3D SLAM sequence (TUM format, e.g. planar_mono)");
  l->add_option("--sequence", slam->sequence, "Sequence folder (rgb/, rgb.txt, calibration.txt, groundtruth.txt)")
      ->required();
  l->add_option("--out", slam->out, "Output dataset folder")->required();
  l->add_option("--max-dt", slam->options.max_dt_s, "Largest frame / ground-truth time difference, seconds")
      ->check(NonNegativeNumber())
      ->capture_default_str();
  l->add_flag("--copy", slam->options.layout.copy_images, "Copy the photos instead of linking them");
  AddCommand(app, l, [slam] {
    CheckConvertOutput(slam->out, {{"--sequence", slam->sequence}});
    const size_t n = ConvertEth3dSlamSequence(slam->sequence, slam->out, slam->options);
    std::cout << "pgba convert eth3d-slam: " << n << " images -> " << slam->out << "/{images/, cameras.txt, gt/}\n";
    return 0;
  });

  struct TanksArgs {
    TanksAndTemplesInput input;
    std::string out;
    DatasetLayoutOptions layout;
  };
  auto tt = std::make_shared<TanksArgs>();
  CLI::App* t = convert->add_subcommand("tanks", "Tanks and Temples scene (*_COLMAP_SfM.log trajectory)");
  t->add_option("--log", tt->input.log_path, "Trajectory SCENE_COLMAP_SfM.log (camera-to-world 4x4 per frame)")
      ->required();
  t->add_option("--images", tt->input.images_dir, "The scene's photos")->required();
  t->add_option("--cameras", tt->input.cameras_path, "COLMAP cameras.txt with the one camera of the scene")
      ->required();
  t->add_option("--image-list", tt->input.image_list,
                "Image names in the order of the log's frames (default: the photos sorted by name)");
  t->add_option("--out", tt->out, "Output dataset folder")->required();
  t->add_flag("--copy", tt->layout.copy_images, "Copy the photos instead of linking them");
  AddCommand(app, t, [tt] {
    CheckConvertOutput(tt->out, {{"--log", tt->input.log_path},
                                 {"--images", tt->input.images_dir},
                                 {"--cameras", tt->input.cameras_path},
                                 {"--image-list", tt->input.image_list}});
    const size_t n = ConvertTanksAndTemples(tt->input, tt->out, tt->layout);
    std::cout << "pgba convert tanks: " << n << " images -> " << tt->out << "/{images/, cameras.txt, gt/}\n";
    return 0;
  });
}

}  // namespace pgba::app
