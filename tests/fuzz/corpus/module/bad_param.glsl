#pragma halo module bad_param
#pragma halo summary "a module whose parameter line is malformed (line 5)"
#pragma halo hook sample
#pragma halo param k_good float default=1 min=0 max=2 "fine"
#pragma halo param k_bad float default=1 minimum=0 "malformed: minimum= is no option"

void apply(inout halo_sample s)
{
    s.opacity = s.opacity * k_good;
}
