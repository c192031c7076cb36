// samples/svg.h — a tiny SVG writer for the demo's pictures (world units in metres, y up).
#pragma once

#include <string>

namespace unison::svg {

/// An SVG document mapping a world rectangle [x0, x1] x [y0, y1] onto `widthPx` pixels (y axis pointing up).
class Picture {
public:
    Picture(double x0, double y0, double x1, double y1, int widthPx);
    void circle(double x, double y, double r, const std::string& fill, const std::string& stroke = "#222");
    void rect(double cx, double cy, double hw, double hh, const std::string& fill, const std::string& stroke = "#222");
    void line(double x0, double y0, double x1, double y1, const std::string& stroke, double widthPx = 2.0);
    /// A closed polygon through world points (xs[i], ys[i]).
    void polygon(const double* xs, const double* ys, int count, const std::string& fill, const std::string& stroke = "#222");
    /// An arrow from (x, y) along (dx, dy), in world units.
    void arrow(double x, double y, double dx, double dy, const std::string& stroke);
    /// Text at a world position; `sizePx` in pixels.
    void text(double x, double y, const std::string& s, double sizePx = 14.0, const std::string& fill = "#111");
    /// Writes the file; returns false when it cannot be written.
    bool save(const std::string& path) const;

private:
    double px(double x) const;
    double py(double y) const;
    double mX0, mY1, mScale;
    int mW, mH;
    std::string mBody;
};

}  // namespace unison::svg
