// samples/svg.cpp — see svg.h.
#include "svg.h"

#include <cmath>
#include <cstdio>
#include <fstream>

namespace unison::svg {
namespace {
std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", v);
    return buf;
}
std::string escape(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '<') out += "&lt;";
        else if (c == '>') out += "&gt;";
        else if (c == '&') out += "&amp;";
        else out += c;
    }
    return out;
}
}  // namespace

Picture::Picture(double x0, double y0, double x1, double y1, int widthPx)
    : mX0(x0), mY1(y1), mScale(widthPx / (x1 - x0)), mW(widthPx), mH(int(std::ceil((y1 - y0) * widthPx / (x1 - x0)))) {}

double Picture::px(double x) const { return (x - mX0) * mScale; }
double Picture::py(double y) const { return (mY1 - y) * mScale; }

void Picture::circle(double x, double y, double r, const std::string& fill, const std::string& stroke) {
    mBody += "<circle cx=\"" + num(px(x)) + "\" cy=\"" + num(py(y)) + "\" r=\"" + num(r * mScale) + "\" fill=\"" + fill +
             "\" stroke=\"" + stroke + "\"/>\n";
}

void Picture::rect(double cx, double cy, double hw, double hh, const std::string& fill, const std::string& stroke) {
    mBody += "<rect x=\"" + num(px(cx - hw)) + "\" y=\"" + num(py(cy + hh)) + "\" width=\"" + num(2 * hw * mScale) +
             "\" height=\"" + num(2 * hh * mScale) + "\" fill=\"" + fill + "\" stroke=\"" + stroke + "\"/>\n";
}

void Picture::line(double x0, double y0, double x1, double y1, const std::string& stroke, double widthPx) {
    mBody += "<line x1=\"" + num(px(x0)) + "\" y1=\"" + num(py(y0)) + "\" x2=\"" + num(px(x1)) + "\" y2=\"" + num(py(y1)) +
             "\" stroke=\"" + stroke + "\" stroke-width=\"" + num(widthPx) + "\"/>\n";
}

void Picture::polygon(const double* xs, const double* ys, int count, const std::string& fill, const std::string& stroke) {
    std::string pts;
    for (int i = 0; i < count; ++i) pts += num(px(xs[i])) + "," + num(py(ys[i])) + " ";
    mBody += "<polygon points=\"" + pts + "\" fill=\"" + fill + "\" stroke=\"" + stroke + "\"/>\n";
}

void Picture::arrow(double x, double y, double dx, double dy, const std::string& stroke) {
    const double len = std::sqrt(dx * dx + dy * dy);
    if (len == 0.0) return;
    line(x, y, x + dx, y + dy, stroke, 3.0);
    const double h = std::min(0.25, 0.4 * len);
    const double ux = dx / len, uy = dy / len;
    const double tx = x + dx, ty = y + dy;
    line(tx, ty, tx - h * ux + 0.5 * h * uy, ty - h * uy - 0.5 * h * ux, stroke, 3.0);
    line(tx, ty, tx - h * ux - 0.5 * h * uy, ty - h * uy + 0.5 * h * ux, stroke, 3.0);
}

void Picture::text(double x, double y, const std::string& s, double sizePx, const std::string& fill) {
    mBody += "<text x=\"" + num(px(x)) + "\" y=\"" + num(py(y)) + "\" font-family=\"sans-serif\" font-size=\"" + num(sizePx) +
             "\" fill=\"" + fill + "\">" + escape(s) + "</text>\n";
}

bool Picture::save(const std::string& path) const {
    std::ofstream out(path, std::ios::binary);
    out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << mW << "\" height=\"" << mH << "\" viewBox=\"0 0 " << mW << " "
        << mH << "\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
        << mBody << "</svg>\n";
    return bool(out);
}

}  // namespace unison::svg
