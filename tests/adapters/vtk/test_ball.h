/* The VTK tests' volume: a ball in a 16^3 image of floats, centred, radius 5 with a
 * value falling linearly from 1 at its centre (ramp), or radius 6 with 1 inside (binary). */
#ifndef HALO_TEST_BALL_H
#define HALO_TEST_BALL_H

#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>

#include <cmath>

static inline vtkSmartPointer<vtkImageData> test_ball(int binary)
{
    const int n = 16;
    vtkSmartPointer<vtkImageData> image = vtkSmartPointer<vtkImageData>::New();
    image->SetDimensions(n, n, n);
    vtkSmartPointer<vtkFloatArray> values = vtkSmartPointer<vtkFloatArray>::New();
    values->SetNumberOfTuples((vtkIdType)n * n * n);
    for (int z = 0, i = 0; z < n; z++)
        for (int y = 0; y < n; y++)
            for (int x = 0; x < n; x++, i++) {
                double r = std::sqrt((x - 7.5) * (x - 7.5) + (y - 7.5) * (y - 7.5) + (z - 7.5) * (z - 7.5));
                values->SetValue(i, binary ? (r < 6.0 ? 1.0f : 0.0f) : (float)(r < 5.0 ? 1.0 - r / 5.0 : 0.0));
            }
    image->GetPointData()->SetScalars(values);
    return image;
}

#endif
