#include "core/features/fast_hessian.h"

#include <algorithm>
#include <cmath>

#include "core/features/integral_box.h"

namespace icgm {

int FastHessianFilterSize(int octave, int interval) {
  return 3 * ((1 << (octave + 1)) * (interval + 1) + 1);
}

namespace {

// A box [x0, x1) x [y0, y1) relative to the sample, as the four integral-image offsets of its
// corners, so that a response costs plain loads from one base pointer.
struct Box {
  int a = 0, b = 0, c = 0, d = 0;  // bottom-right, bottom-left, top-right, top-left
  Box() = default;
  Box(int stride, int x0, int y0, int x1, int y1)
      : a(y1 * stride + x1), b(y1 * stride + x0), c(y0 * stride + x1), d(y0 * stride + x0) {}
  int Sum(const int* p) const { return p[a] - p[b] - p[c] + p[d]; }
};

// The three box filters of side L (Bay et al. 2008, fig. 1), normalised by the area L^2.
struct BoxHessian {
  Box yy_outer, yy_middle, xx_outer, xx_middle, xy_tl, xy_br, xy_tr, xy_bl;
  float inv_area = 0.0f;

  BoxHessian(int filter_size, int stride) {
    const int lobe = filter_size / 3;  // odd
    const int half = filter_size / 2;  // (L - 1) / 2
    const int mid = (lobe - 1) / 2;
    inv_area = 1.0f / static_cast<float>(filter_size * filter_size);
    // Dyy: a (2 lobe - 1) wide, 3 lobe tall box with weights +1, -2, +1 along y (the whole box
    // minus 3 times its middle lobe); Dxx the same transposed.
    yy_outer = Box(stride, -lobe + 1, -half, lobe, half + 1);
    yy_middle = Box(stride, -lobe + 1, -mid, lobe, mid + 1);
    xx_outer = Box(stride, -half, -lobe + 1, half + 1, lobe);
    xx_middle = Box(stride, -mid, -lobe + 1, mid + 1, lobe);
    // Dxy: four lobe x lobe boxes around the centre pixel, +1 on the diagonal quadrants.
    xy_tl = Box(stride, -lobe, -lobe, 0, 0);
    xy_br = Box(stride, 1, 1, lobe + 1, lobe + 1);
    xy_tr = Box(stride, 1, -lobe, lobe + 1, 0);
    xy_bl = Box(stride, -lobe, 1, 0, lobe + 1);
  }

  float Dxx(const int* p) const {
    return static_cast<float>(xx_outer.Sum(p) - 3 * xx_middle.Sum(p)) * inv_area;
  }
  float Dyy(const int* p) const {
    return static_cast<float>(yy_outer.Sum(p) - 3 * yy_middle.Sum(p)) * inv_area;
  }
  float Dxy(const int* p) const {
    return static_cast<float>(xy_tl.Sum(p) + xy_br.Sum(p) - xy_tr.Sum(p) - xy_bl.Sum(p)) * inv_area;
  }
  // det = Dxx Dyy - (0.9 Dxy)^2 (eq. 3 of the 2008 paper).
  float Determinant(const int* p) const {
    const float dxy = Dxy(p);
    return Dxx(p) * Dyy(p) - 0.81f * dxy * dxy;
  }
};

// Determinant-of-Hessian responses of one filter size on the octave's sampling grid. Samples
// whose filter leaves the image stay 0.
struct ResponseLayer {
  int filter_size = 0;
  cv::Mat det;     // CV_32F, grid rows x grid cols
  int border = 0;  // first valid grid index in x and y
};

// `storage` is (re)allocated to the grid's size when it differs and shared by the layer.
ResponseLayer ComputeLayer(const cv::Mat& integral, int filter_size, int step, int grid_cols,
                           int grid_rows, cv::Mat* storage) {
  ResponseLayer layer;
  layer.filter_size = filter_size;
  storage->create(grid_rows, grid_cols, CV_32F);
  layer.det = *storage;
  const int cols = integral.cols - 1;
  const int rows = integral.rows - 1;
  const int stride = static_cast<int>(integral.step1());
  const BoxHessian hessian(filter_size, stride);
  const int half = filter_size / 2;
  // A sample at pixel p uses pixels [p - half, p + half].
  const int first = (half + step - 1) / step;
  layer.border = first;
  const int last_x = std::min((cols - half - 1) / step, grid_cols - 1);
  const int last_y = std::min((rows - half - 1) / step, grid_rows - 1);
  const int* base = integral.ptr<int>(0);
  // Samples whose filter leaves the image are 0 (the buffer may hold an earlier image's).
  for (int r = 0; r < grid_rows; ++r) {
    float* det_row = layer.det.ptr<float>(r);
    if (r < first || r > last_y) {
      std::fill(det_row, det_row + grid_cols, 0.0f);
      continue;
    }
    std::fill(det_row, det_row + std::min(first, grid_cols), 0.0f);
    if (last_x + 1 < grid_cols) {
      std::fill(det_row + std::max(last_x + 1, 0), det_row + grid_cols, 0.0f);
    }
  }
  for (int r = first; r <= last_y; ++r) {
    float* det_row = layer.det.ptr<float>(r);
    const int* row = base + r * step * stride;
    if (step == 1) {  // contiguous reads in the first octave
      for (int c = first; c <= last_x; ++c) det_row[c] = hessian.Determinant(row + c);
    } else {
      for (int c = first; c <= last_x; ++c) det_row[c] = hessian.Determinant(row + c * step);
    }
  }
  return layer;
}

// Sign of the Laplacian Dxx + Dyy at a sample: -1 bright blob, +1 dark blob.
int LaplacianSign(const cv::Mat& integral, int filter_size, int x, int y) {
  const BoxHessian hessian(filter_size, static_cast<int>(integral.step1()));
  const int* p = integral.ptr<int>(y) + x;
  return hessian.Dxx(p) + hessian.Dyy(p) >= 0.0f ? 1 : -1;
}

bool IsLocalMaximum(const ResponseLayer* layers[3], int r, int c, float value) {
  for (int l = 0; l < 3; ++l) {
    for (int dr = -1; dr <= 1; ++dr) {
      const float* row = layers[l]->det.ptr<float>(r + dr);
      for (int dc = -1; dc <= 1; ++dc) {
        if (l == 1 && dr == 0 && dc == 0) continue;
        if (row[c + dc] >= value) return false;
      }
    }
  }
  return true;
}

// Fits a quadratic to the 3x3x3 neighbourhood; false when the fit is degenerate or the
// extremum lies a sample or more away.
bool Interpolate(const ResponseLayer* layers[3], int r, int c, cv::Vec3d* offset, double* value) {
  auto at = [&](int l, int dr, int dc) {
    return static_cast<double>(layers[l]->det.at<float>(r + dr, c + dc));
  };
  const double v = at(1, 0, 0);
  const cv::Vec3d g((at(1, 0, 1) - at(1, 0, -1)) / 2.0, (at(1, 1, 0) - at(1, -1, 0)) / 2.0,
                    (at(2, 0, 0) - at(0, 0, 0)) / 2.0);
  const double dxx = at(1, 0, 1) + at(1, 0, -1) - 2 * v;
  const double dyy = at(1, 1, 0) + at(1, -1, 0) - 2 * v;
  const double dss = at(2, 0, 0) + at(0, 0, 0) - 2 * v;
  const double dxy = (at(1, 1, 1) - at(1, 1, -1) - at(1, -1, 1) + at(1, -1, -1)) / 4.0;
  const double dxs = (at(2, 0, 1) - at(2, 0, -1) - at(0, 0, 1) + at(0, 0, -1)) / 4.0;
  const double dys = (at(2, 1, 0) - at(2, -1, 0) - at(0, 1, 0) + at(0, -1, 0)) / 4.0;
  const cv::Matx33d h(dxx, dxy, dxs, dxy, dyy, dys, dxs, dys, dss);
  cv::Vec3d x;
  if (!cv::solve(h, -g, x, cv::DECOMP_LU)) return false;
  if (std::abs(x[0]) >= 1.0 || std::abs(x[1]) >= 1.0 || std::abs(x[2]) >= 1.0) return false;
  *offset = x;
  *value = v + 0.5 * g.dot(x);
  return true;
}

}  // namespace

std::vector<HessianBlob> DetectFastHessian(const cv::Mat& integral,
                                           const FastHessianOptions& options,
                                           FastHessianBuffers* buffers) {
  std::vector<HessianBlob> blobs;
  FastHessianBuffers local;
  if (buffers == nullptr) buffers = &local;
  const size_t layer_count =
      static_cast<size_t>(std::max(0, options.octaves) * std::max(0, options.intervals));
  if (buffers->layers.size() < layer_count) buffers->layers.resize(layer_count);
  if (integral.empty() || integral.type() != CV_32S || options.intervals < 3) return blobs;
  const int cols = integral.cols - 1;
  const int rows = integral.rows - 1;
  const float threshold = static_cast<float>(options.hessian_threshold);
  for (int octave = 0; octave < options.octaves; ++octave) {
    const int step = 1 << octave;
    const int grid_cols = cols / step;
    const int grid_rows = rows / step;
    // The largest filter of the octave must fit with a sample around it.
    if (FastHessianFilterSize(octave, options.intervals - 1) + 2 * step > std::min(cols, rows)) {
      break;
    }
    std::vector<ResponseLayer> layers;
    for (int i = 0; i < options.intervals; ++i) {
      cv::Mat* storage = &buffers->layers[static_cast<size_t>(octave * options.intervals + i)];
      layers.push_back(ComputeLayer(integral, FastHessianFilterSize(octave, i), step, grid_cols,
                                    grid_rows, storage));
    }
    const double size_step = 6.0 * step;  // filter-size difference of adjacent intervals
    for (int i = 1; i + 1 < options.intervals; ++i) {
      const ResponseLayer* trio[3] = {&layers[i - 1], &layers[i], &layers[i + 1]};
      // Neighbours in the largest filter must be valid.
      const int first = layers[i + 1].border + 1;
      const int last_x = (cols - layers[i + 1].filter_size / 2 - 1) / step - 1;
      const int last_y = (rows - layers[i + 1].filter_size / 2 - 1) / step - 1;
      for (int r = first; r <= last_y && r + 1 < grid_rows; ++r) {
        const float* row = layers[i].det.ptr<float>(r);
        for (int c = first; c <= last_x && c + 1 < grid_cols; ++c) {
          const float value = row[c];
          if (value <= threshold || !IsLocalMaximum(trio, r, c, value)) continue;
          cv::Vec3d offset;
          double interpolated = 0.0;
          if (!Interpolate(trio, r, c, &offset, &interpolated)) continue;
          HessianBlob b;
          b.position_px = cv::Point2f(static_cast<float>((c + offset[0]) * step),
                                      static_cast<float>((r + offset[1]) * step));
          b.filter_size_px = static_cast<float>(layers[i].filter_size + offset[2] * size_step);
          b.scale_px = 1.2f * b.filter_size_px / 9.0f;
          b.response = static_cast<float>(interpolated);
          b.laplacian_sign = LaplacianSign(integral, layers[i].filter_size, c * step, r * step);
          b.octave = octave;
          blobs.push_back(b);
        }
      }
    }
  }
  std::sort(blobs.begin(), blobs.end(),
            [](const HessianBlob& a, const HessianBlob& b) { return a.response > b.response; });
  return blobs;
}

}  // namespace icgm
