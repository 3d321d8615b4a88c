#include "core/features/surf.h"

#include <cmath>

#include <opencv2/imgproc.hpp>

#include "core/features/surf_descriptor.h"

namespace icgm {

void ExtractSurf(const cv::Mat& gray, const SurfOptions& options,
                 std::vector<cv::KeyPoint>* keypoints, cv::Mat* descriptors, SurfBuffers* buffers) {
  keypoints->clear();
  *descriptors = cv::Mat(0, kSurfDescriptorSize, CV_32F);
  if (gray.empty() || gray.type() != CV_8UC1) return;
  SurfBuffers local;
  if (buffers == nullptr) buffers = &local;
  cv::Mat& integral = buffers->integral;
  cv::integral(gray, integral, CV_32S);
  std::vector<HessianBlob> blobs = DetectFastHessian(integral, options.detector, &buffers->hessian);
  if (options.max_keypoints > 0 && static_cast<int>(blobs.size()) > options.max_keypoints) {
    blobs.resize(options.max_keypoints);  // strongest first
  }
  *descriptors = cv::Mat(static_cast<int>(blobs.size()), kSurfDescriptorSize, CV_32F);
  keypoints->reserve(blobs.size());
  constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;
  for (size_t k = 0; k < blobs.size(); ++k) {
    const HessianBlob& b = blobs[k];
    const double angle =
        options.upright ? 0.0 : SurfOrientation(integral, b.position_px, b.scale_px);
    SurfDescribe(integral, b.position_px, b.scale_px, angle,
                 descriptors->ptr<float>(static_cast<int>(k)));
    double degrees = angle * kRadToDeg;
    if (degrees < 0.0) degrees += 360.0;
    if (degrees >= 360.0) degrees -= 360.0;
    keypoints->emplace_back(b.position_px, b.filter_size_px, static_cast<float>(degrees),
                            b.response, b.octave, b.laplacian_sign);
  }
}

}  // namespace icgm
