# Equilibrium run for Einstein-Helfand, MB and MSD: same model and box as in.nemd (no push).
units           lj
dimension       3
boundary        p p p
atom_style      atomic
comm_modify     vel yes
variable        L     index 5.0
variable        steps index 100000
variable        seed  index 34387
region          box block -${L} ${L} $(-v_L/2) $(v_L/2) $(-v_L/2) $(v_L/2)
create_box      1 box
create_atoms    1 random $(3*2*v_L^3) 8675 box
mass            1 1.0
velocity        all create 1.0 4928 mom yes dist gaussian
pair_style      dpd/nonlinear 1.0 1.0 ${seed}
pair_coeff      1 1 25.0 4.5 0.0
neighbor        0.3 bin
neigh_modify    delay 0 every 1 check yes
timestep        0.01
fix             1 all nve
thermo          1000
run             2000
reset_timestep  0
fix             press all ave/time 1 1 1 c_thermo_press[4] c_thermo_press[5] c_thermo_press[6] file press.ave
compute         msd all msd
fix             msd all ave/time 100 1 100 c_msd[4] file msd.ave
variable        speed atom sqrt(vx*vx+vy*vy+vz*vz)
fix             hist all ave/histo 10 100 1000 0.0 5.0 100 v_speed mode vector file speed.histo
dump            traj all custom 200 traj.dump id xu yu zu vx vy vz
dump_modify     traj sort id
thermo_style    custom step temp press pxy pxz pyz
run             ${steps}
