// SURF against images with known answers: Gaussian blobs of known centres and widths (the
// detector recovers both, and the Laplacian sign tells bright from dark), and a textured image
// rotated and scaled by a known similarity (keypoints repeat, descriptors match, orientations
// turn with the image).
#include "core/features/surf.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "../icgm/synthetic_scene.h"
#include "core/features/descriptor_matcher.h"
#include "core/features/fast_hessian.h"
#include "core/features/feature_extractor.h"

namespace icgm {
namespace {

struct Blob {
  cv::Point2d centre_px;
  double sigma_px;
  double amplitude;  // > 0 bright, < 0 dark
};

cv::Mat RenderBlobs(const cv::Size& size, const std::vector<Blob>& blobs) {
  cv::Mat image(size, CV_64F, cv::Scalar(110.0));
  for (int y = 0; y < size.height; ++y) {
    for (int x = 0; x < size.width; ++x) {
      double v = 0.0;
      for (const Blob& b : blobs) {
        const double d2 =
            (x - b.centre_px.x) * (x - b.centre_px.x) + (y - b.centre_px.y) * (y - b.centre_px.y);
        v += b.amplitude * std::exp(-d2 / (2.0 * b.sigma_px * b.sigma_px));
      }
      image.at<double>(y, x) += v;
    }
  }
  cv::Mat out;
  image.convertTo(out, CV_8U);
  return out;
}

TEST(SurfTest, FilterSizesFollowThePaper) {
  EXPECT_EQ(FastHessianFilterSize(0, 0), 9);
  EXPECT_EQ(FastHessianFilterSize(0, 3), 27);
  EXPECT_EQ(FastHessianFilterSize(1, 0), 15);
  EXPECT_EQ(FastHessianFilterSize(1, 3), 51);
  EXPECT_EQ(FastHessianFilterSize(2, 1), 51);
  EXPECT_EQ(FastHessianFilterSize(3, 3), 195);
}

TEST(SurfTest, GaussianBlobsGivePositionScaleAndLaplacianSign) {
  const std::vector<Blob> blobs = {{{120.3, 110.6}, 2.5, 120.0},
                                   {{380.7, 130.2}, 4.0, 120.0},
                                   {{130.4, 370.5}, 6.0, -90.0},
                                   {{375.2, 385.8}, 9.0, 120.0}};
  const cv::Mat image = RenderBlobs(cv::Size(512, 512), blobs);
  SurfOptions options;
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  ExtractSurf(image, options, &keypoints, &descriptors);
  ASSERT_EQ(descriptors.rows, static_cast<int>(keypoints.size()));
  ASSERT_GE(keypoints.size(), blobs.size());
  std::vector<double> scale_ratios;
  for (const Blob& b : blobs) {
    // The strongest keypoint near the blob's centre.
    const cv::KeyPoint* found = nullptr;
    for (const cv::KeyPoint& k : keypoints) {
      if (std::hypot(k.pt.x - b.centre_px.x, k.pt.y - b.centre_px.y) > b.sigma_px) continue;
      if (!found || k.response > found->response) found = &k;
    }
    ASSERT_NE(found, nullptr) << "no keypoint at blob sigma " << b.sigma_px;
    EXPECT_NEAR(found->pt.x, b.centre_px.x, 0.1 * b.sigma_px + 0.3) << b.sigma_px;
    EXPECT_NEAR(found->pt.y, b.centre_px.y, 0.1 * b.sigma_px + 0.3) << b.sigma_px;
    scale_ratios.push_back(SurfScale(*found) / b.sigma_px);
    EXPECT_EQ(found->class_id, b.amplitude > 0 ? -1 : 1) << b.sigma_px;
  }
  // The scale follows the blob's width. The paper's s = 1.2 L / 9 is the scale of the cropped
  // Gaussian the 9x9 filter approximates; the box Dyy's middle lobe (side L / 3) puts its zero
  // crossings at +-L / 6, where a Gaussian second derivative of scale sigma has them at
  // +-sigma: the box acts like sigma = L / 6 = 1.25 s, so a blob of width sigma peaks near
  // s = 0.8 sigma.
  for (const double r : scale_ratios) {
    EXPECT_GT(r, 0.65);
    EXPECT_LT(r, 0.85);
  }
  const auto [lo, hi] = std::minmax_element(scale_ratios.begin(), scale_ratios.end());
  EXPECT_LT(*hi / *lo, 1.2);
  // Nothing on the flat background as strong as the weakest blob.
  float weakest = 1e30f;
  for (const Blob& b : blobs) {
    for (const cv::KeyPoint& k : keypoints) {
      if (std::hypot(k.pt.x - b.centre_px.x, k.pt.y - b.centre_px.y) < b.sigma_px) {
        weakest = std::min(weakest, k.response);
      }
    }
  }
  for (const cv::KeyPoint& k : keypoints) {
    bool near_blob = false;
    for (const Blob& b : blobs) {
      near_blob |= std::hypot(k.pt.x - b.centre_px.x, k.pt.y - b.centre_px.y) < 4 * b.sigma_px;
    }
    if (!near_blob) {
      EXPECT_LT(k.response, weakest) << k.pt;
    }
  }
}

TEST(SurfTest, HigherThresholdGivesFewerKeypoints) {
  const cv::Mat image = test::MakeTexture(cv::Size(320, 240), 7);
  cv::Mat gray;
  cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  SurfOptions low, high;
  low.max_keypoints = high.max_keypoints = 0;
  high.detector.hessian_threshold = 20 * low.detector.hessian_threshold;
  std::vector<cv::KeyPoint> k_low, k_high;
  cv::Mat d;
  ExtractSurf(gray, low, &k_low, &d);
  ExtractSurf(gray, high, &k_high, &d);
  EXPECT_GT(k_low.size(), k_high.size());
  for (const cv::KeyPoint& k : k_high) EXPECT_GT(k.response, high.detector.hessian_threshold);
  // Descriptors have unit length.
  ExtractSurf(gray, high, &k_high, &d);
  for (int r = 0; r < d.rows; ++r) EXPECT_NEAR(cv::norm(d.row(r)), 1.0, 1e-4);
}

// Buffers kept between calls change nothing: two textured images of one size (the second
// reuses the first's layers), a smaller one and the first again give the keypoints and
// descriptors of calls without buffers.
TEST(SurfTest, ReusedBuffersGiveTheSameResult) {
  cv::Mat big, other, small;
  cv::cvtColor(test::MakeTexture(cv::Size(320, 240), 7), big, cv::COLOR_BGR2GRAY);
  cv::cvtColor(test::MakeTexture(cv::Size(320, 240), 9), other, cv::COLOR_BGR2GRAY);
  cv::cvtColor(test::MakeTexture(cv::Size(200, 150), 3), small, cv::COLOR_BGR2GRAY);
  SurfOptions options;
  options.max_keypoints = 0;
  SurfBuffers buffers;
  for (const cv::Mat* image : {&big, &other, &small, &big}) {
    std::vector<cv::KeyPoint> fresh, reused;
    cv::Mat d_fresh, d_reused;
    ExtractSurf(*image, options, &fresh, &d_fresh);
    ExtractSurf(*image, options, &reused, &d_reused, &buffers);
    ASSERT_GT(fresh.size(), 20u);
    ASSERT_EQ(fresh.size(), reused.size());
    for (size_t k = 0; k < fresh.size(); ++k) {
      EXPECT_EQ(fresh[k].pt, reused[k].pt);
      EXPECT_EQ(fresh[k].size, reused[k].size);
      EXPECT_EQ(fresh[k].response, reused[k].response);
    }
    EXPECT_EQ(cv::norm(d_fresh, d_reused, cv::NORM_INF), 0.0);
  }
}

struct WarpedPair {
  cv::Mat a, b;
  cv::Matx33d h;  // a -> b
};

WarpedPair RotatedScaled(double angle_deg, double scale) {
  WarpedPair p;
  cv::Mat texture = test::MakeTexture(cv::Size(640, 480), 11);
  cv::cvtColor(texture, p.a, cv::COLOR_BGR2GRAY);
  cv::GaussianBlur(p.a, p.a, cv::Size(0, 0), 1.0);
  const cv::Mat m = cv::getRotationMatrix2D(cv::Point2f(320, 240), angle_deg, scale);
  cv::warpAffine(p.a, p.b, m, p.a.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
  p.h = cv::Matx33d(m.at<double>(0, 0), m.at<double>(0, 1), m.at<double>(0, 2), m.at<double>(1, 0),
                    m.at<double>(1, 1), m.at<double>(1, 2), 0, 0, 1);
  return p;
}

cv::Point2d Map(const cv::Matx33d& h, cv::Point2f p) {
  const cv::Vec3d q = h * cv::Vec3d(p.x, p.y, 1.0);
  return {q[0] / q[2], q[1] / q[2]};
}

// Share of a's keypoints, mapped inside b (away from the reflected border), that have a
// keypoint of b within 2.5 px whose scale agrees within 30 %.
double Repeatability(const WarpedPair& p, const FeatureSet& a, const FeatureSet& b, double scale) {
  int inside = 0, repeated = 0;
  for (const cv::KeyPoint& ka : a.keypoints) {
    const cv::Point2d q = Map(p.h, ka.pt);
    if (q.x < 40 || q.y < 40 || q.x > 600 || q.y > 440) continue;
    ++inside;
    for (const cv::KeyPoint& kb : b.keypoints) {
      if (std::hypot(kb.pt.x - q.x, kb.pt.y - q.y) < 2.5 &&
          std::abs(kb.size / (ka.size * scale) - 1.0) < 0.3) {
        ++repeated;
        break;
      }
    }
  }
  return inside > 0 ? static_cast<double>(repeated) / inside : 0.0;
}

TEST(SurfTest, RotatedAndScaledImagesRepeatAndMatch) {
  const double angle_deg = 30.0, scale = 1.3;
  const WarpedPair p = RotatedScaled(angle_deg, scale);
  FeatureOptions options;
  options.detector = Detector::kSurf;
  options.max_features = 600;
  auto surf = FeatureExtractor::Create(options);
  const FeatureSet a = surf->Extract(p.a);
  const FeatureSet b = surf->Extract(p.b);
  ASSERT_GT(a.size(), 300u);
  ASSERT_GT(b.size(), 300u);
  EXPECT_GT(Repeatability(p, a, b, scale), 0.5);

  const std::vector<cv::DMatch> matches = DescriptorMatcher(MatcherOptions()).Match(a, b);
  int correct = 0;
  std::vector<double> angle_errors;
  for (const cv::DMatch& m : matches) {
    const cv::KeyPoint& ka = a.keypoints[m.queryIdx];
    const cv::KeyPoint& kb = b.keypoints[m.trainIdx];
    if (std::hypot(Map(p.h, ka.pt).x - kb.pt.x, Map(p.h, ka.pt).y - kb.pt.y) > 3.0) continue;
    ++correct;
    // getRotationMatrix2D turns counter-clockwise on screen: image-frame angles decrease.
    double e = std::fmod(kb.angle - (ka.angle - angle_deg) + 540.0, 360.0) - 180.0;
    angle_errors.push_back(std::abs(e));
  }
  EXPECT_GT(correct, 150);
  EXPECT_GT(static_cast<double>(correct) / matches.size(), 0.8);
  ASSERT_FALSE(angle_errors.empty());
  std::nth_element(angle_errors.begin(), angle_errors.begin() + angle_errors.size() / 2,
                   angle_errors.end());
  EXPECT_LT(angle_errors[angle_errors.size() / 2], 5.0);
}

TEST(SurfTest, UprightMatchesScaleChangeButNotLargeRotation) {
  FeatureOptions options;
  options.detector = Detector::kSurf;
  options.max_features = 600;
  options.surf_upright = true;
  auto usurf = FeatureExtractor::Create(options);
  const DescriptorMatcher matcher{MatcherOptions()};
  auto correct_matches = [&](const WarpedPair& p) {
    const FeatureSet a = usurf->Extract(p.a);
    const FeatureSet b = usurf->Extract(p.b);
    int correct = 0;
    for (const cv::DMatch& m : matcher.Match(a, b)) {
      const cv::Point2d q = Map(p.h, a.keypoints[m.queryIdx].pt);
      const cv::Point2f kb = b.keypoints[m.trainIdx].pt;
      correct += std::hypot(q.x - kb.x, q.y - kb.y) < 3.0;
    }
    return correct;
  };
  const int scaled = correct_matches(RotatedScaled(0.0, 1.3));
  const int rotated = correct_matches(RotatedScaled(60.0, 1.0));
  EXPECT_GT(scaled, 150);
  EXPECT_LT(rotated, scaled / 3);
}

}  // namespace
}  // namespace icgm
