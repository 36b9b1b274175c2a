#pragma once
#include <QElapsedTimer>
#include <cstdio>
struct GmTrace { const char* n; QElapsedTimer t; GmTrace(const char* n_) : n(n_) { t.start(); } ~GmTrace() { double ms = t.nsecsElapsed()*1e-6; if (ms > 4) std::fprintf(stderr, "TRACE %s %.1f ms\n", n, ms); } };
